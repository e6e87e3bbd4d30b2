"""RViz on a virtual screen, for the tests that look at it (imported, not a
node): background processes that log to files, Xvfb on a display number
it picks itself, the 3D view of a screenshot with the arrow colours of
the package's views (sim.rviz: red /odom; nav_ekf.rviz: green /odom_ekf;
both: blue ground truth), screenshots polled until the picture shows, and
where a top-down view draws the arrows of a stream of poses.

Used by test/integration/test_rviz_views.py and
test/rostest/book_lines_test.py.
"""
import importlib
import math
import os
import select
import subprocess
import time

import numpy as np

# Arrow colours of the configs, as RViz shades them on a dark background:
# the pixel counts of each must pass MIN_PIXELS. Each takes r, g, b as
# numbers or as numpy arrays (a mask).
RED = lambda r, g, b: (r > 170) & (g < 90) & (b < 70)                 # noqa: E731
GREEN = lambda r, g, b: (g > 140) & (r < 90) & (b < 110)              # noqa: E731
BLUE = lambda r, g, b: (b > 170) & (r < 60) & (80 < g) & (g < 200)    # noqa: E731
MIN_PIXELS = 150
#: Wall seconds a picture may take to show: a hang guard, not a measure
#: (RViz draws on the wall clock, slowly on a loaded machine).
PICTURE_LIMIT = 240.0
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
#: The virtual screen's tools and the Debian packages that hold them (in
#: the Makefile's DEB_PACKAGES: make deps installs them).
XVFB, IMAGE_GRAB = '/usr/bin/Xvfb', 'PIL.ImageGrab'
SCREEN_DEBS = {XVFB: 'xvfb', IMAGE_GRAB: 'python3-pil'}


def require_screen():
    """Fail, naming the package, when Xvfb or PIL.ImageGrab is missing: a
    test that skipped without them would read as a pass."""
    assert os.path.exists(XVFB), '%s is not installed: make deps installs %s' % (
        XVFB, SCREEN_DEBS[XVFB])
    try:
        importlib.import_module(IMAGE_GRAB)
    except ImportError as err:
        raise AssertionError('%s: make deps installs %s' % (err, SCREEN_DEBS[IMAGE_GRAB]))


def view_of(shot):
    """The 3D view of a screenshot, as an (rows, columns, 3) int array (so
    the panels' blue and red text cannot pass for arrows): the box of the
    rows and columns in which a tenth of the pixels or more are the
    background's. (Not the box around every background pixel: the panels'
    dark text has some, and that box was nearly the whole window.)"""
    pixels = np.asarray(shot.convert('RGB'), dtype=int)
    background = (pixels == BACKGROUND).all(axis=2)
    rows = np.nonzero(background.sum(axis=1) >= 0.1 * background.shape[1])[0]
    columns = np.nonzero(background.sum(axis=0) >= 0.1 * background.shape[0])[0]
    assert rows.size and columns.size, 'no 3D view (background %s) on the screen' % (
        BACKGROUND,)
    return pixels[rows[0]:rows[-1] + 1, columns[0]:columns[-1] + 1]


def colour_mask(view, match):
    """The pixels of ``view`` (:func:`view_of`) a colour predicate matches."""
    return match(view[..., 0], view[..., 1], view[..., 2])


def colour_counts(shot, colours):
    """{name: pixels of that colour in the 3D view of ``shot``} for
    ``colours`` ({name: predicate on r, g, b})."""
    view = view_of(shot)
    return {name: int(np.count_nonzero(colour_mask(view, match)))
            for name, match in colours.items()}


def wait_for_picture(display, rviz, log, ready, what=lambda shot: '',
                     limit=PICTURE_LIMIT, every=0.5):
    """Screenshots of ``display`` until ``ready(shot)`` is true: (the shot,
    wall seconds it took). Fails at once when RViz (the process ``rviz``,
    logging to ``log()``) has exited, and after ``limit`` s, naming the
    time waited and ``what(shot)`` of the last shot."""
    from PIL import ImageGrab
    began = time.monotonic()
    while True:
        assert rviz.poll() is None, 'RViz exited after %.1f s:\n%s' % (
            time.monotonic() - began, log())
        shot = ImageGrab.grab(xdisplay=display)
        if ready(shot):
            return shot, time.monotonic() - began
        waited = time.monotonic() - began
        assert waited < limit, 'the picture did not show in %.0f s: %s' % (
            waited, what(shot))
        time.sleep(every)


def top_down_view(config):
    """The 3D view of an RViz config (parsed YAML) whose view is
    TopDownOrtho with angle 0: (pixels per metre, the fixed frame's x and y
    at the view's centre)."""
    view = config['Visualization Manager']['Views']['Current']
    assert view['Class'] == 'rviz/TopDownOrtho' and view['Angle'] == 0, view
    return float(view['Scale']), float(view['X']), float(view['Y'])


def arrows_area(shape, poses, view, arrow, margin):
    """The pixels of a top-down view (an array ``shape``: rows, columns)
    where arrows at any of ``poses`` ((x, y, yaw) in the fixed frame) would
    be drawn, and ``margin`` pixels around them: a boolean array.

    ``view`` is :func:`top_down_view`'s; ``arrow`` the display's Shape
    (Shaft Length, Shaft Radius, Head Length, Head Radius, metres): RViz
    draws an arrow from the pose along its heading. An arrow RViz keeps
    for one of the poses lies inside."""
    from PIL import Image, ImageDraw, ImageFilter
    scale, x0, y0 = view
    rows, columns = shape
    shaft, shaft_r = float(arrow['Shaft Length']), float(arrow['Shaft Radius'])
    head, head_r = float(arrow['Head Length']), float(arrow['Head Radius'])
    outline = [(0.0, shaft_r), (shaft, shaft_r), (shaft, head_r), (shaft + head, 0.0),
               (shaft, -head_r), (shaft, -shaft_r), (0.0, -shaft_r)]
    mask = Image.new('L', (columns, rows), 0)
    draw = ImageDraw.Draw(mask)
    for x, y, yaw in poses:
        c, s = math.cos(yaw), math.sin(yaw)
        draw.polygon([(columns / 2.0 + scale * (x + c * a - s * b - x0),
                       rows / 2.0 - scale * (y + s * a + c * b - y0))
                      for a, b in outline], fill=255)
    mask = mask.filter(ImageFilter.MaxFilter(2 * margin + 1))
    return np.asarray(mask) > 0


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
        picking one free number at once would share a screen); sets DISPLAY.
        Fails at once without Xvfb or PIL.ImageGrab (:func:`require_screen`)."""
        require_screen()
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
