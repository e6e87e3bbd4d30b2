"""rbx1_nav.common.cmd_vel_watch: each other publisher of a cmd_vel named once."""
from rbx1_nav.common.cmd_vel_watch import NewPublishers, warning_text


def test_a_course_names_each_other_publisher_once():
    check = NewPublishers(own='/odom_out_and_back')
    assert check.update(['/odom_out_and_back']) == []
    assert check.update(['/odom_out_and_back', '/teleop_keyboard']) == ['/teleop_keyboard']
    assert check.update(['/odom_out_and_back', '/teleop_keyboard']) == []
    assert check.update(['/teleop_keyboard', '/joy_teleop',
                         '/odom_out_and_back']) == ['/joy_teleop']


def test_the_robot_warns_once_two_publish():
    check = NewPublishers()
    assert check.update(['/odom_out_and_back']) == []
    assert check.update([]) == []
    assert check.update(['/odom_out_and_back', '/teleop_keyboard']) == [
        '/odom_out_and_back', '/teleop_keyboard']
    assert check.update(['/odom_out_and_back', '/teleop_keyboard']) == []
    # One left, then a new second one: only the new one is news.
    assert check.update(['/teleop_keyboard']) == []
    assert check.update(['/teleop_keyboard', '/nav_square']) == ['/nav_square']


def test_the_warning_names_the_node_and_the_fix():
    text = warning_text('/cmd_vel', ['/teleop_keyboard'],
                        ['/odom_out_and_back', '/teleop_keyboard'],
                        own='/odom_out_and_back')
    assert text.startswith('/teleop_keyboard also publishes on /cmd_vel;')
    assert 'rosnode kill /teleop_keyboard' in text
    robot = warning_text('/cmd_vel', ['/a', '/b'], ['/a', '/b'])
    assert robot.startswith('2 nodes publish on /cmd_vel: /a, /b;')


# -- OtherDriver: another node commanding motion while a course drives ------

from rbx1_nav.common.cmd_vel_watch import (OtherDriver, is_motion,  # noqa: E402
                                           other_driver_text)

STILL = ((0.0, 0.0, 0.0), (0.0, 0.0, 0.0))
FORWARD = ((0.2, 0.0, 0.0), (0.0, 0.0, 0.0))


def test_only_a_motion_command_from_another_node_while_armed_is_a_fight():
    check = OtherDriver(own='/odom_out_and_back')
    # Disarmed (between a calibration's tests): the user may drive by hand.
    assert not check.heard('/teleop_keyboard', *FORWARD)
    check.arm()
    assert not check.heard('/odom_out_and_back', *FORWARD)  # its own
    assert not check.heard('/teleop_keyboard', *STILL)      # a stop: warned only
    assert check.found is None
    assert check.heard('/nav_square', (0.0, 0.0, 0.0), (0.0, 0.0, 0.7))
    assert check.found == ('/nav_square', 0.0, 0.7)
    # The first one found is kept.
    assert not check.heard('/teleop_keyboard', *FORWARD)
    assert check.found[0] == '/nav_square'
    check.disarm()
    check.arm()  # the next course starts clean
    assert check.found is None


def test_every_component_and_nan_count_as_motion():
    assert not is_motion((0.0, 0.0, 0.0), (0.0, -0.0, 0.0))
    for index in range(3):
        triple = [0.0, 0.0, 0.0]
        triple[index] = 1e-3
        assert is_motion(triple, (0.0, 0.0, 0.0))
        assert is_motion((0.0, 0.0, 0.0), triple)
    assert is_motion((float('nan'), 0.0, 0.0), (0.0, 0.0, 0.0))


def test_the_fight_line_names_the_node_topic_and_fix():
    text = other_driver_text('/cmd_vel', ('/nav_square', 0.2, 0.0))
    assert text.startswith('/nav_square commanded the robot on /cmd_vel '
                           '(0.2 m/s, 0 rad/s) while this course drove it')
    assert 'Stopped the robot.' in text
    assert 'rosnode kill /nav_square' in text and 'remap' in text
    assert '\n' not in text
