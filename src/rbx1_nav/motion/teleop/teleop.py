"""Keyboard teleoperation as plain logic: key map, speeds, key-release timeout.

No rospy here: rbx1_nav.motion.teleop.teleop_ros (teleop_keyboard.py's ROS side)
reads keys from the terminal, feeds them (or None when no key came) with
the time to :meth:`KeyboardTeleop.feed`, publishes the (linear, angular)
command it returns and shows :meth:`KeyboardTeleop.status`. Tests drive the
same class with a fake clock.

The layout is teleop_twist_keyboard's; the robot heads towards the key's
place around ``k``, reversing like a car for ``m`` and ``.``::

    u  i  o      forward-left   forward    forward-right
    j  k  l      turn left      stop       turn right
    m  ,  .      back-left      backward   back-right

``k`` or space stops, and so does any key not in the map (an arrow key, a
letter typed with Caps Lock on). ``q``/``z`` raise/lower both speeds by 10 %,
``w``/``x`` the linear speed only, ``e``/``c`` the angular speed only; never
above the maximums. ``Q`` or Ctrl-C quits.

A terminal reports key presses but no key releases: a held key arrives as a
stream of repeats. So a motion lasts ``key_timeout`` seconds after its last
key press; with no motion key for that long the command drops to zero.
Speed keys do not extend a motion.
"""
from rbx1_nav.common import params
from rbx1_nav.motion.course.command import MAX_ANGULAR_SPEED, MAX_LINEAR_SPEED, STOP, Command
from rbx1_nav.common.params import param

__all__ = ['MOTION_KEYS', 'STOP_KEYS', 'SPEED_KEYS',
           'QUIT_KEYS', 'PARAMS', 'check_settings', 'Speeds',
           'KeyboardTeleop', 'help_text', 'POLL', 'NOT_A_TERMINAL']

# key: (sign of linear speed, sign of angular speed, name); angular > 0 is
# counter-clockwise (left), as in REP 103.
MOTION_KEYS = {
    'i': (1, 0, 'forward'),
    ',': (-1, 0, 'backward'),
    'j': (0, 1, 'turn left'),
    'l': (0, -1, 'turn right'),
    'u': (1, 1, 'forward-left'),
    'o': (1, -1, 'forward-right'),
    'm': (-1, -1, 'back-left'),
    '.': (-1, 1, 'back-right'),
}
STOP_KEYS = ('k', ' ')
# key: (factor on the linear speed, factor on the angular speed, name)
SPEED_KEYS = {
    'q': (1.1, 1.1, 'speeds up'), 'z': (0.9, 0.9, 'speeds down'),
    'w': (1.1, 1.0, 'linear speed up'), 'x': (0.9, 1.0, 'linear speed down'),
    'e': (1.0, 1.1, 'angular speed up'), 'c': (1.0, 0.9, 'angular speed down'),
}
QUIT_KEYS = ('Q', '\x03')  # Q, or Ctrl-C (a key, not a signal: ISIG is off)
POLL = 0.1  # s: the longest wait for a key, also how often a shutdown is noticed

NOT_A_TERMINAL = (
    'teleop_keyboard needs a keyboard: its stdin is not a terminal. Run it '
    'with rosrun in a terminal, or roslaunch in the foreground of a terminal, '
    'or in a launch file with launch-prefix="xterm -e" (keyboard_teleop.launch'
    ' launch_prefix:="xterm -e").')


# The node's private parameters. The package-wide speed limits of
# rbx1_nav.motion.course.command bound the maximums; each speed must be within its maximum.
PARAMS = (
    param('linear_speed', 0.2, params.number, 'm/s',
          'forward speed at start', **params.POSITIVE),
    param('angular_speed', 1.0, params.number, 'rad/s',
          'turn rate at start', **params.POSITIVE),
    param('max_linear_speed', 1.0, params.number, 'm/s',
          'the keys never raise the forward speed above this',
          maximum=MAX_LINEAR_SPEED, **params.POSITIVE),
    param('max_angular_speed', 3.0, params.number, 'rad/s',
          'the keys never raise the turn rate above this',
          maximum=MAX_ANGULAR_SPEED, **params.POSITIVE),
    param('key_timeout', 0.8, params.number, 's',
          'stop when no motion key came for this long',
          maximum=10.0, **params.POSITIVE),
    param('rate', 10.0, params.number, 'Hz',
          'cmd_vel repeat rate while a motion key is held',
          minimum=1.0, maximum=100.0),
)


def check_settings(lookup, node_name='/teleop_keyboard', given=frozenset()):
    """Read and check the node's parameters; return {name: float}.

    ``lookup(name, default)`` gives a raw value (for the node, its private
    namespace's). Raises ValueError naming every unusable value, with '~'
    before each name as the user writes it, and the ``rosparam delete``
    that clears each not in ``given`` (the command line's, which a refused
    node leaves off the master) from the node ``node_name``; a speed above
    its maximum is reported once the values themselves pass.
    """
    values = params.check_all(PARAMS, lookup, node_name, given)
    too_fast = [speed for speed in ('linear_speed', 'angular_speed')
                if values[speed] > values['max_' + speed]]
    if too_fast:
        stored = [speed for speed in too_fast if speed not in given]
        raise ValueError('. '.join(['; '.join(
            '~%s must be <= ~max_%s (%g), got %g' % (
                speed, speed, values['max_' + speed], values[speed])
            for speed in too_fast)] + ([params.clear_text(node_name, stored)] if stored else [])))
    return values


class Speeds(object):
    """The speeds the motion keys use; steps never go above the maximums."""

    def __init__(self, linear, angular, max_linear, max_angular):
        self.linear, self.angular = linear, angular
        self.max_linear, self.max_angular = max_linear, max_angular

    def scale(self, linear_factor, angular_factor):
        """Multiply the speeds, capped; return the names of capped ones."""
        self.linear = min(self.linear * linear_factor, self.max_linear)
        self.angular = min(self.angular * angular_factor, self.max_angular)
        return [name for name, factor, value, top in (
            ('linear', linear_factor, self.linear, self.max_linear),
            ('angular', angular_factor, self.angular, self.max_angular))
            if factor > 1.0 and value >= top]


class KeyboardTeleop(object):
    """Keys in, velocity commands out, with the key-release timeout.

    Call :meth:`update` with each key (a one-character string) or None, and
    a time in seconds from a clock that never jumps.
    """

    def __init__(self, linear_speed=0.2, angular_speed=1.0,
                 max_linear_speed=1.0, max_angular_speed=3.0,
                 key_timeout=0.8):
        self.speeds = Speeds(linear_speed, angular_speed, max_linear_speed,
                             max_angular_speed)
        self.key_timeout = key_timeout
        self.direction = (0, 0)   # signs of (linear, angular)
        self.pressed_at = None    # time of the last motion key
        self.last = 'waiting for a key'
        self.quit = False

    @classmethod
    def from_settings(cls, settings):
        """The teleop for :func:`check_settings`'s values (all but the
        ``rate``, which is the node's cmd_vel repeat)."""
        return cls(**dict((name, value) for name, value in settings.items()
                          if name != 'rate'))

    @property
    def moving(self):
        return self.direction != (0, 0)

    def _stop(self, why):
        self.direction, self.pressed_at = (0, 0), None
        self.last = why

    def update(self, key, now):
        """Take one key (or None) at time ``now``; return the Command.

        After a quit key every key is ignored and the command stays zero.
        """
        if self.quit:
            return STOP
        if key in MOTION_KEYS:
            linear, angular, name = MOTION_KEYS[key]
            self.direction, self.pressed_at = (linear, angular), now
            self.last = '%r %s' % (key, name)
        elif key in SPEED_KEYS:
            linear, angular, name = SPEED_KEYS[key]
            capped = self.speeds.scale(linear, angular)
            self.last = '%r %s' % (key, name)
            if capped:
                self.last += ' (%s at max)' % ' and '.join(capped)
        elif key in QUIT_KEYS:
            self._stop('quit')
            self.quit = True
        elif key in STOP_KEYS:
            self._stop('%r stop' % key)
        elif key is not None:
            self._stop('%r is no command key: stop' % key)
        if self.moving and now - self.pressed_at >= self.key_timeout:
            self._stop('key released: stop')
        return self.command()

    def feed(self, keys, now):
        """Take the keys of one read at ``now`` ('' when none came, None
        once the terminal hung up: as good as a quit key); return the
        Command after the last."""
        if keys is None:
            keys = QUIT_KEYS[0]
        for key in keys or [None]:
            command = self.update(key, now)
        return command

    def command(self):
        """The Command for the current direction and speeds."""
        return Command(self.direction[0] * self.speeds.linear,
                       self.direction[1] * self.speeds.angular)

    def release_in(self, now):
        """Seconds until the motion times out; None when not moving."""
        if not self.moving:
            return None
        return max(0.0, self.pressed_at + self.key_timeout - now)

    def read_timeout(self, now, until_send, poll=POLL):
        """Seconds to wait for a key at ``now``: ``poll``, and while moving
        no longer than until the motion times out or until the command's
        repeat is due (``until_send`` s from now, negative when overdue)."""
        if not self.moving:
            return poll
        return min(poll, self.release_in(now), max(0.0, until_send))

    def status(self):
        """One line: the speeds, the command and the last key's effect."""
        command = self.command()
        return 'speed %.2f m/s turn %.2f rad/s | cmd %+.2f %+.2f | %s' % (
            self.speeds.linear, self.speeds.angular, command.linear,
            command.angular, self.last)


def help_text(key_timeout):
    """The key help the node prints at start-up."""
    return '\n'.join((
        'Keyboard teleop: hold a key to move, release it to stop.',
        'To quit: Q (capital: lowercase q speeds up) or Ctrl-C.',
        '',
        '   u    i    o       forward-left  forward   forward-right',
        '   j    k    l       turn left     stop      turn right',
        '   m    ,    .       back-left     backward  back-right',
        '',
        'k, space or any other key: stop. The robot also stops %.1f s after '
        'the last' % key_timeout,
        'motion key (terminals report no key release).',
        'q/z: both speeds +/-10 %   w/x: linear only   e/c: angular only',
        'Q (capital) or Ctrl-C: stop the robot and quit.',
    ))
