"""RViz on a virtual screen, for the tests that look at it (imported, not a
node): background processes that log to files, Xvfb on a display number
it picks itself, and the 3D view of a screenshot with the arrow colours of
the package's views (sim.rviz: red /odom; nav_ekf.rviz: green /odom_ekf;
both: blue ground truth).

Used by test/integration/test_rviz_views.py and
test/rostest/book_lines_test.py.
"""
import os
import select
import subprocess

# Arrow colours of the configs, as RViz shades them on a dark background:
# the pixel counts of each must pass MIN_PIXELS.
RED = lambda r, g, b: r > 170 and g < 90 and b < 70             # noqa: E731
GREEN = lambda r, g, b: g > 140 and r < 90 and b < 110           # noqa: E731
BLUE = lambda r, g, b: b > 170 and r < 60 and 80 < g < 200       # noqa: E731
MIN_PIXELS = 150
BACKGROUND = (48, 48, 48)  # the configs' 3D view background
#: What RViz needs beside DISPLAY on a virtual screen. Software GL:
#: RViz 1.14.19 with Mesa 22.3's llvmpipe corrupts its heap now and then
#: in its first frames (SIGSEGV or "free(): invalid next size" under
#: glXSwapBuffers): 9 of 59 starts beside a CPU burner, and as often
#: without the config's panels, its RobotModel or its Odometry displays,
#: with llvmpipe single-threaded, 128-bit vectors or without MIT-SHM.
#: Mesa's softpipe, which needs no LLVM, crashed in 1 of 58 beside it.
#: The cause, inside RViz or Mesa, is not found.
RVIZ_ENV = {'LIBGL_ALWAYS_SOFTWARE': '1', 'GALLIUM_DRIVER': 'softpipe', 'QT_X11_NO_MITSHM': '1'}


def view_of(shot):
    """The 3D view of a screenshot: the box around its background pixels
    (so the panels' blue and red text cannot pass for arrows)."""
    width = shot.width
    where = [i for i, p in enumerate(shot.getdata()) if p == BACKGROUND]
    assert where, 'no 3D view (background %s) on the screen' % (BACKGROUND,)
    xs = [i % width for i in where]
    return shot.crop((min(xs), where[0] // width, max(xs) + 1,
                      where[-1] // width + 1))


def colour_counts(shot, colours):
    """{name: pixels of that colour in the 3D view of ``shot``} for
    ``colours`` ({name: predicate on r, g, b})."""
    pixels = list(view_of(shot.convert('RGB')).getdata())
    return {name: sum(1 for p in pixels if match(*p))
            for name, match in colours.items()}


def rviz_errors(log):
    """The lines of an RViz log that RViz logged as errors."""
    return [line for line in log.splitlines() if '[ERROR]' in line]


class Processes(object):
    """Background processes, each logging to a file; all killed at the end."""

    def __init__(self, env, logdir):
        self.env, self.logdir, self.procs = env, logdir, []

    def start(self, name, args, **popen):
        log = open(os.path.join(self.logdir, name + '.log'), 'w')
        proc = subprocess.Popen(args, env=self.env, stdout=log, stderr=subprocess.STDOUT,
                                start_new_session=True, **popen)
        self.procs.append(proc)
        return proc

    def start_xvfb(self):
        """A virtual screen on a display number Xvfb picks itself (two tests
        picking one free number at once would share a screen); sets DISPLAY."""
        read, write = os.pipe()
        try:
            self.start('xvfb', ['Xvfb', '-displayfd', str(write), '-screen', '0',
                                '1280x800x24', '-nolisten', 'tcp'], pass_fds=(write,))
        finally:
            os.close(write)
        with os.fdopen(read) as answer:  # the number once it listens, EOF if it died
            number = answer.readline().strip() if select.select([answer], [], [], 30)[0] else ''
        assert number, 'Xvfb did not start:\n' + self.log('xvfb')
        self.env['DISPLAY'] = ':' + number
        return self.env['DISPLAY']

    def log(self, name):
        with open(os.path.join(self.logdir, name + '.log')) as f:
            return f.read()

    def stop_one(self, proc):
        """Ctrl-C to ``proc``'s process group; killed if it lingers."""
        if proc.poll() is None:
            os.killpg(proc.pid, 2)  # SIGINT, as Ctrl-C
            try:
                proc.wait(15)
            except subprocess.TimeoutExpired:
                os.killpg(proc.pid, 9)
                proc.wait()

    def stop(self):
        for proc in reversed(self.procs):
            self.stop_one(proc)
