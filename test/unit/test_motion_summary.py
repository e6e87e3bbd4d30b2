"""The motion runner's rospy-free pieces: its summary line and its remap hint."""
import math
from types import SimpleNamespace

from rbx1_nav.motion.course.stalls import Stalls
from rbx1_nav.motion.runner.cmd_vel import listener_hint
from rbx1_nav.motion.course.summary import stalls_text, summary_line
from rbx1_nav.transform_utils import Pose2D


def _course(start, end, elapsed):
    return SimpleNamespace(elapsed=elapsed, start_pose=start,
                           ideal_end=lambda pose: end)


def _stalls(count, seconds):
    stalls = Stalls(0.1)
    stalls.count, stalls.seconds = count, seconds
    return stalls


def test_stalls_text():
    assert stalls_text(_stalls(0, 0.0), '/odom', True) == 'never'
    assert stalls_text(_stalls(3, 1.25), '/odom', True) == (
        '3 times, 1.2 s in all (its watchdog, or commands late)')
    assert stalls_text(_stalls(3, 1.25), '/robot1/odom', False) == (
        'unknown (nothing on /robot1/odom)')


def test_summary_line_with_a_final_pose():
    start = Pose2D(1.0, 2.0, 0.0)
    course = _course(start, Pose2D(1.0, 2.0, math.pi), 44.64)
    final = Pose2D(1.0012, 1.9995, math.radians(179.5))
    ticks = [k * 0.05 for k in range(201)]  # 20 Hz for 10 s
    assert summary_line('robot1: ', course, final, 'odom', ticks, 'never',
                        'never') == (
        'robot1: Course complete in 44.6 s: final pose relative to start in '
        'odom: dx +1.2 mm, dy -0.5 mm, dyaw +179.50 deg; error from the ideal '
        'end pose: position 1.3 mm, heading -0.50 deg; control loop 20.0 Hz '
        'mean, 20 Hz slowest second; stood still while commanded: never; '
        'link dropouts ridden out: never')


def test_summary_line_blind():
    course = _course(None, None, 20.25)
    assert summary_line('', course, None, 'odom', [0.0], 'unknown (nothing on '
                        '/odom)', '1 time, 2.0 s in all') == (
        'Course complete in 20.2 s (no odometry: final pose unknown); stood '
        'still while commanded: unknown (nothing on /odom); link dropouts '
        'ridden out: 1 time, 2.0 s in all')


def test_listener_hint():
    assert listener_hint(None, '/course', '/cmd_vel') == 'is the robot driver running?'
    graph = ({}, {'/odom': ['/ekf'], '/mobile_base/commands/velocity': ['/base'],
                  '/cmd_vel_mux/input': ['/mux']},
             {'/odom': 'nav_msgs/Odometry',
              '/mobile_base/commands/velocity': 'geometry_msgs/Twist',
              '/cmd_vel_mux/input': 'geometry_msgs/Twist'})
    assert listener_hint(graph, '/course', '/cmd_vel') == (
        'these topics take Twist commands: /cmd_vel_mux/input, '
        '/mobile_base/commands/velocity. Remap to the driver\'s, e.g. '
        'cmd_vel:=/cmd_vel_mux/input')
    assert listener_hint(({}, {'/odom': ['/ekf']}, {'/odom': 'nav_msgs/Odometry'}),
                         '/course', '/cmd_vel') == (
        'no node takes geometry_msgs/Twist commands: is the robot driver '
        'running?')


def test_listener_hint_skips_the_courses_own_subscriptions():
    """A TurtleBot 2 driver on mobile_base/commands/velocity, the course on
    /cmd_vel, which it hears itself (the second-driver watch), and a topic
    only the course hears: the hint names the driver's topic alone."""
    graph = ({}, {'/cmd_vel': ['/course'],
                  '/mobile_base/commands/velocity': ['/mobile_base'],
                  '/another_cmd': ['/course']},
             {'/cmd_vel': 'geometry_msgs/Twist',
              '/mobile_base/commands/velocity': 'geometry_msgs/Twist',
              '/another_cmd': 'geometry_msgs/Twist'})
    assert listener_hint(graph, '/course', '/cmd_vel') == (
        'these topics take Twist commands: /mobile_base/commands/velocity. '
        'Remap to the driver\'s, e.g. cmd_vel:=/mobile_base/commands/velocity')
