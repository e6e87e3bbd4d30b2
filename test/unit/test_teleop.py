"""Unit tests for rbx1_nav.motion.teleop.teleop: keyboard teleop keys, speeds, timeout."""
import math

import pytest

from rbx1_nav.motion.course.command import MAX_ANGULAR_SPEED
from rbx1_nav.motion.teleop.teleop import (MOTION_KEYS, NOT_A_TERMINAL, PARAMS, POLL, QUIT_KEYS,
                                    SPEED_KEYS, STOP_KEYS, KeyboardTeleop, Speeds, check_settings,
                                    help_text)
from rbx1_nav.motion.course.command import STOP

DEFAULTS = dict((spec.name, spec.default) for spec in PARAMS)


def settings(**raw):
    """check_settings() on the defaults with ``raw`` values set."""
    return check_settings(lambda name, default: raw.get(name, default))


def teleop(**options):
    settings = dict(linear_speed=0.2, angular_speed=1.0, max_linear_speed=1.0,
                    max_angular_speed=3.0, key_timeout=0.6)
    settings.update(options)
    return KeyboardTeleop(**settings)


# --- key map -----------------------------------------------------------------

@pytest.mark.parametrize('key,linear,angular', [
    ('i', 0.2, 0.0), (',', -0.2, 0.0), ('j', 0.0, 1.0), ('l', 0.0, -1.0),
    ('u', 0.2, 1.0), ('o', 0.2, -1.0), ('m', -0.2, -1.0), ('.', -0.2, 1.0)])
def test_motion_keys_command_the_speeds_in_teleop_twist_keyboard_layout(
        key, linear, angular):
    t = teleop()
    assert t.update(key, 0.0) == (linear, angular)
    assert t.moving and not t.quit


@pytest.mark.parametrize('key', list(STOP_KEYS) + ['I', '\x1b', '[', 'A', 'y'])
def test_stop_keys_and_unknown_keys_stop(key):
    t = teleop()
    assert t.update('u', 0.0) != STOP
    assert t.update(key, 0.1) == STOP
    assert not t.moving and not t.quit


def test_key_groups_do_not_overlap():
    groups = [set(MOTION_KEYS), set(STOP_KEYS), set(SPEED_KEYS),
              set(QUIT_KEYS)]
    assert sum(len(g) for g in groups) == len(set.union(*groups))
    assert set(STOP_KEYS) == {'k', ' '}
    assert set(QUIT_KEYS) == {'Q', '\x03'}


@pytest.mark.parametrize('key', QUIT_KEYS)
def test_quit_stops_and_every_later_key_is_ignored(key):
    t = teleop()
    t.update('i', 0.0)
    assert t.update(key, 0.1) == STOP
    assert t.quit
    for later in ('i', 'q', 'j', None):
        assert t.update(later, 0.2) == STOP
    assert t.speeds.linear == 0.2 and 'quit' in t.status()


def test_no_key_before_any_key_is_a_stop():
    t = teleop()
    assert t.update(None, 0.0) == STOP
    assert t.release_in(0.0) is None


# --- speeds ------------------------------------------------------------------

@pytest.mark.parametrize('key,linear,angular', [
    ('q', 0.22, 1.1), ('z', 0.18, 0.9), ('w', 0.22, 1.0), ('x', 0.18, 1.0),
    ('e', 0.2, 1.1), ('c', 0.2, 0.9)])
def test_speed_keys_step_by_ten_percent(key, linear, angular):
    t = teleop()
    assert t.update(key, 0.0) == STOP  # a speed key alone does not move
    assert t.speeds.linear == pytest.approx(linear)
    assert t.speeds.angular == pytest.approx(angular)


def test_speed_keys_change_a_motion_in_progress():
    t = teleop()
    t.update('u', 0.0)
    assert t.update('q', 0.1) == pytest.approx((0.22, 1.1))
    assert t.update('x', 0.2) == pytest.approx((0.198, 1.1))


def test_speeds_never_exceed_the_maximums():
    t = teleop(max_linear_speed=0.5, max_angular_speed=1.5)
    for step in range(50):
        t.update('q', 0.0)
    assert (t.speeds.linear, t.speeds.angular) == (0.5, 1.5)
    assert 'linear and angular at max' in t.last
    t.update('e', 0.0)
    assert t.last == "'e' angular speed up (angular at max)"
    assert t.update('o', 0.0) == (0.5, -1.5)


def test_speeds_at_their_maximum_step_back_down():
    speeds = Speeds(1.0, 3.0, 1.0, 3.0)
    assert speeds.scale(1.1, 1.1) == ['linear', 'angular']
    assert speeds.scale(0.9, 1.0) == []
    assert (speeds.linear, speeds.angular) == (pytest.approx(0.9), 3.0)


def test_lowering_keeps_speeds_positive():
    t = teleop()
    for step in range(100):
        t.update('z', 0.0)
    assert 0.0 < t.speeds.linear < 0.2 * 0.9 ** 99
    assert t.update('i', 0.0).linear > 0.0


# --- key-release timeout -----------------------------------------------------

def test_motion_stops_key_timeout_after_the_last_motion_key():
    t = teleop(key_timeout=0.6)
    assert t.update('i', 10.0) == (0.2, 0.0)
    assert t.update(None, 10.59) == (0.2, 0.0)
    assert t.release_in(10.59) == pytest.approx(0.01)
    assert t.update(None, 10.601) == STOP
    assert 'released' in t.last and t.release_in(10.601) is None
    assert t.update(None, 20.0) == STOP


def test_held_key_repeats_keep_the_motion_going():
    t = teleop(key_timeout=0.6)
    now = 0.0
    t.update('j', now)
    while now < 5.0:  # a terminal's auto-repeat: a key every 40 ms
        now += 0.04
        assert t.update('j', now) == (0.0, 1.0)
    assert t.update(None, now + 0.59) == (0.0, 1.0)
    assert t.update(None, now + 0.61) == STOP


def test_speed_keys_do_not_extend_a_motion():
    t = teleop(key_timeout=0.6)
    t.update('i', 0.0)
    assert t.update('q', 0.5) == pytest.approx((0.22, 0.0))
    assert t.update('w', 0.7) == STOP


def test_a_new_motion_key_restarts_the_timeout():
    t = teleop(key_timeout=1.0)
    t.update('i', 0.0)
    assert t.update('l', 0.9) == (0.0, -1.0)
    assert t.update(None, 1.8) == (0.0, -1.0)
    assert t.update(None, 1.901) == STOP


# --- status and help ---------------------------------------------------------

def test_status_shows_speeds_command_and_last_key():
    t = teleop()
    assert t.status() == ('speed 0.20 m/s turn 1.00 rad/s | cmd +0.00 +0.00 '
                          '| waiting for a key')
    t.update('m', 0.0)
    assert t.status() == ("speed 0.20 m/s turn 1.00 rad/s | cmd -0.20 -1.00 "
                          "| 'm' back-left")
    t.update('q', 0.0)
    assert t.status().startswith('speed 0.22 m/s turn 1.10 rad/s | cmd -0.22 '
                                 '-1.10 |')
    assert t.status().endswith("'q' speeds up")


def test_help_names_every_key_and_the_timeout():
    text = help_text(0.6)
    for key in list(MOTION_KEYS) + list(SPEED_KEYS) + ['Q', 'Ctrl-C', 'space']:
        assert key in text
    assert '0.6 s' in text
    assert max(len(line) for line in text.splitlines()) < 80
    # How to quit is on the first screen, before the keys: q is a speed key.
    assert text.splitlines()[1] == 'To quit: Q (capital: lowercase q speeds up) or Ctrl-C.'


# --- settings ----------------------------------------------------------------

def test_defaults_are_the_documented_ones_and_pass_the_checks():
    assert DEFAULTS == dict(linear_speed=0.2, angular_speed=1.0,
                            max_linear_speed=1.0, max_angular_speed=3.0,
                            key_timeout=0.8, rate=10.0)
    assert settings() == DEFAULTS


def test_settings_accept_numeric_strings():
    values = settings(linear_speed='0.5', rate=20)
    assert values['linear_speed'] == 0.5 and values['rate'] == 20.0
    assert all(type(value) is float for value in values.values())


@pytest.mark.parametrize('name,value,message', [
    ('linear_speed', 0.0, '~linear_speed must be > 0'),
    ('angular_speed', math.nan, '~angular_speed must be a finite number'),
    ('max_linear_speed', 20.0, '~max_linear_speed must be > 0 and <= 2,'),
    ('max_angular_speed', -1.0, '~max_angular_speed must be > 0'),
    ('max_angular_speed', 7.0, '~max_angular_speed must be > 0 and <= 6.28'),
    ('key_timeout', 0, '~key_timeout must be > 0'),
    ('key_timeout', 600, '~key_timeout must be > 0 and <= 10,'),
    ('rate', 0.5, '~rate must be >= 1'),
    ('rate', 'fast', '~rate must be a number'),
    ('linear_speed', True, '~linear_speed must be a number')])
def test_bad_settings_are_named(name, value, message):
    with pytest.raises(ValueError) as err:
        settings(**{name: value})
    assert message in str(err.value)


def test_speeds_must_be_within_their_maximums():
    with pytest.raises(ValueError) as err:
        settings(linear_speed=1.5, angular_speed=3.5)
    assert str(err.value) == (
        '~linear_speed must be <= ~max_linear_speed (1), got 1.5; '
        '~angular_speed must be <= ~max_angular_speed (3), got 3.5. On the '
        'parameter server, not from this command line (an earlier run, a '
        'launch file or rosparam set): clear it with rosparam delete '
        '/teleop_keyboard/linear_speed; rosparam delete /teleop_keyboard/angular_speed')
    assert settings(linear_speed=1.5, max_linear_speed=1.5,
                    max_angular_speed=MAX_ANGULAR_SPEED)['linear_speed'] == 1.5


def test_every_bad_setting_is_reported_at_once():
    with pytest.raises(ValueError) as err:
        settings(linear_speed=-1, key_timeout='x')
    assert '~linear_speed' in str(err.value)
    assert '~key_timeout' in str(err.value)
    assert str(err.value).endswith(
        'rosparam delete /teleop_keyboard/linear_speed; '
        'rosparam delete /teleop_keyboard/key_timeout')


def test_a_bad_setting_from_the_command_line_has_no_rosparam_delete():
    # A refused node leaves the command line's values off the master
    # (rbx1_nav.common.params_given): nothing there to delete.
    values = dict(linear_speed=1.5, angular_speed=3.5)
    with pytest.raises(ValueError) as err:
        check_settings(lambda name, default: values.get(name, default), given={'linear_speed'})
    assert str(err.value).endswith(
        'got 3.5. On the parameter server, not from this command line (an earlier run, a '
        'launch file or rosparam set): clear it with rosparam delete '
        '/teleop_keyboard/angular_speed')
    with pytest.raises(ValueError) as err:
        check_settings(lambda name, default: values.get(name, default),
                       given={'linear_speed', 'angular_speed'})
    assert 'rosparam' not in str(err.value) and str(err.value).endswith('got 3.5')


# --- one read of the terminal at a time --------------------------------------

def test_a_read_of_several_keys_takes_each_in_turn():
    t = teleop()
    assert t.feed('iw', 0.0) == (pytest.approx(0.22), 0.0)
    assert t.last == "'w' linear speed up"
    assert t.feed('ik', 0.1) == STOP


def test_a_read_with_no_key_still_times_the_motion_out():
    t = teleop(key_timeout=0.5)
    t.feed('i', 0.0)
    assert t.feed('', 0.4) == (0.2, 0.0)
    assert t.feed('', 0.5) == STOP and t.last == 'key released: stop'


def test_a_hang_up_quits():
    t = teleop()
    t.feed('i', 0.0)
    assert t.feed(None, 0.1) == STOP and t.quit


def test_from_settings_leaves_the_rate_to_the_node():
    t = KeyboardTeleop.from_settings(settings(linear_speed=0.3, rate=50,
                                              key_timeout=2))
    assert (t.speeds.linear, t.key_timeout) == (0.3, 2.0)
    assert t.speeds.max_angular == DEFAULTS['max_angular_speed']


def test_the_wait_for_a_key_ends_at_the_timeout_or_the_next_repeat():
    t = teleop(key_timeout=0.6)
    assert t.read_timeout(0.0, -5.0) == POLL == 0.1  # not moving: just poll
    t.feed('i', 10.0)
    assert t.read_timeout(10.0, 1.0) == POLL
    assert t.read_timeout(10.55, 1.0) == pytest.approx(0.05)  # the timeout
    assert t.read_timeout(10.0, 0.03) == pytest.approx(0.03)  # the repeat
    assert t.read_timeout(10.0, -0.2) == 0.0  # a repeat overdue
    assert t.read_timeout(10.0, 1.0, poll=0.5) == pytest.approx(0.5)


def test_without_a_terminal_the_node_says_how_to_run_it():
    assert NOT_A_TERMINAL.startswith('teleop_keyboard needs a keyboard')
    assert 'launch-prefix="xterm -e"' in NOT_A_TERMINAL
