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


# -- what the other node is, and what a user may be told to type -------------

from rbx1_nav.common.cmd_vel_watch import (COURSE, COURSE_HEADER,  # noqa: E402
                                           DRIVER_PROCESS, PUBLISHER, UNKNOWN,
                                           is_course, kind_of, mux_input,
                                           refused_text)

VELOCITY = '/mobile_base/commands/velocity'
MANAGER = '/mobile_base_nodelet_manager'


def test_a_node_that_takes_the_topic_is_the_drivers_process():
    assert kind_of(MANAGER, [MANAGER], set()) == DRIVER_PROCESS
    assert kind_of('/nav_square', [MANAGER, '/nav_square'], {'/nav_square'}) == COURSE
    assert kind_of('/teleop_keyboard', [MANAGER], set()) == PUBLISHER
    assert is_course(dict([COURSE_HEADER, ('callerid', '/nav_square')]))
    assert not is_course({'callerid': MANAGER}) and not is_course(None)


def test_the_remap_is_the_multiplexers_own_navigation_input():
    twist = 'geometry_msgs/Twist'
    subscribers = {VELOCITY: [MANAGER], '/cmd_vel_mux/input/teleop': [MANAGER],
                   '/cmd_vel_mux/input/navi': [MANAGER], '/other/navi': ['/elsewhere']}
    types = dict.fromkeys(subscribers, twist)
    assert mux_input(MANAGER, subscribers, types, VELOCITY) == '/cmd_vel_mux/input/navi'
    del subscribers['/cmd_vel_mux/input/navi']
    assert mux_input(MANAGER, subscribers, types, VELOCITY) == '/cmd_vel_mux/input/teleop'
    # A driver with no multiplexer input the master knows: TurtleBot 2's.
    assert mux_input(MANAGER, {VELOCITY: [MANAGER]}, types, VELOCITY) == '/cmd_vel_mux/input/navi'


def test_no_kill_is_offered_for_a_node_that_may_be_the_driver():
    for kind in (DRIVER_PROCESS, UNKNOWN):
        warning = warning_text(VELOCITY, [MANAGER], ['/odom_out_and_back', MANAGER],
                               own='/odom_out_and_back',
                               kinds={MANAGER: (kind, '/cmd_vel_mux/input/navi')})
        fight = other_driver_text(VELOCITY, (MANAGER, 0.1, 0.0), kind,
                                  '/cmd_vel_mux/input/navi')
        refused = refused_text(VELOCITY, (MANAGER, 0.1, 0.0), kind, '/cmd_vel_mux/input/navi')
        for text in (warning, fight, refused):
            assert 'rosnode kill' not in text, text
            assert '\n' not in text
    for text in (warning_text(VELOCITY, [MANAGER], [MANAGER], own='/c',
                              kinds={MANAGER: (DRIVER_PROCESS, '/cmd_vel_mux/input/navi')}),
                 other_driver_text(VELOCITY, (MANAGER, 0.1, 0.0), DRIVER_PROCESS,
                                   '/cmd_vel_mux/input/navi')):
        assert 'velocity multiplexer' in text
        assert 'cmd_vel:=/cmd_vel_mux/input/navi' in text


def test_a_refused_course_says_it_left_the_robot_to_the_other():
    text = refused_text('/cmd_vel', ('/odom_out_and_back', 0.2, 0.0), COURSE)
    assert text.startswith('did not start: /odom_out_and_back is driving the robot on /cmd_vel '
                           '(0.2 m/s, 0 rad/s), so this course left the robot to it and sent '
                           'nothing. ')
    # Stopping the other course is a choice, for a stale one.
    assert 'if it is stale' in text and 'rosnode kill /odom_out_and_back' in text


def test_a_course_hears_who_drives_before_its_first_command():
    check = OtherDriver(own='/nav_square')
    check.heard('/odom_out_and_back', (0.2, 0, 0), (0, 0, 0), course=True)
    check.listen()  # what came before it listens does not count
    assert check.driving is None
    check.heard('/nav_square', *FORWARD, course=True)   # its own
    check.heard('/teleop_keyboard', *STILL)            # a teleop at rest
    assert check.driving is None
    check.heard('/odom_out_and_back', *STILL, course=True)  # a course's stop is driving
    assert check.driving == ('/odom_out_and_back', 0.0, 0.0)
    check.heard('/teleop_keyboard', *FORWARD)  # the first one heard is kept
    assert check.driving[0] == '/odom_out_and_back'
    assert check.found is None  # not armed: no fight
