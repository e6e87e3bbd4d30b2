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
