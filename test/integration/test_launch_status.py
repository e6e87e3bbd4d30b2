"""A launch's end, as a script sees it.

launch_status.py exits with the course's status (roslaunch exits 0 even
when a required course failed), and a course's launch leaves none of its
parameters behind: a plain rosrun afterwards runs with its defaults (a
launch with sim_speed:=5 record:=true once left start_delay 10 s and
tf_wait 25 s, and the next rosrun waited 10 s before moving), judged by
the robot's ground truth: it moves at once and drives the default course.
The courses run under lockstep simulated time
(rbx1_nav.common.launch_end for the launches'), the later rosrun's ending
where the pure model of the default course does."""
import math
import os
import re
import subprocess
import sys

import pytest

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import test_second_robot  # noqa: E402
from test_second_robot import rosrun  # noqa: E402

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), '..', 'helpers'))
from course_model import reference_end_pose  # noqa: E402

Graph = test_second_robot.Graph
pytestmark = test_second_robot.pytestmark

HANG_GUARD = test_second_robot.HANG_GUARD


@pytest.fixture
def graph(tmp_path):
    g = Graph(tmp_path)
    yield g
    g.close()


def launch_status(graph, *args):
    return graph.run(rosrun('rbx1_nav', 'launch_status.py', 'rbx1_nav', *args),
                     timeout=HANG_GUARD)


def course_logs(log_dir, node):
    """Every log file of ``node`` under ``log_dir``, joined."""
    text = []
    for path in sorted(log_dir.rglob('*%s*.log' % node)):
        text.append(path.read_text(errors='replace'))
    return '\n'.join(text)


#: The head of one record in a node's log file: ``[logger][LEVEL] date time: ``.
LOG_RECORD = re.compile(r'^\[([\w.]+)\]\[[A-Z]+\] \d{4}-\d\d-\d\d ', re.M)


def without_shutdown_races(logs):
    """``logs`` without rospy's own transport records (rospy.internal) from the
    node's signal_shutdown on: closing a connection at shutdown while its
    receive thread reads it makes rospy log that thread's traceback
    (tcpros_base.receive_once, a race inside rospy), whatever the node did."""
    heads = list(LOG_RECORD.finditer(logs))
    kept, shutting_down = [], False
    for head, following in zip(heads, heads[1:] + [None]):
        record = logs[head.start():following.start() if following else len(logs)]
        shutting_down = shutting_down or 'signal_shutdown' in record
        if not (shutting_down and head.group(1) == 'rospy.internal'):
            kept.append(record)
    return logs[:heads[0].start()] + ''.join(kept) if heads else logs


def test_launch_status_exits_with_the_courses_status(graph, tmp_path):
    before = set(graph.master.getParamNames())
    done = launch_status(graph, 'nav_square.launch', 'sim:=true', 'sim_speed:=max')
    assert done.returncode == 0, done.stdout[-4000:]
    assert 'Course complete' in done.stdout
    assert done.stdout.rstrip().endswith('launch_status: nav_square exited 0'), done.stdout[-2000:]
    # The launch set /use_sim_time and /lockstep for its nodes; its clock
    # removed them as it ended: the master's simulated time as before it.
    after = set(graph.master.getParamNames())
    assert not {'/use_sim_time', '/lockstep'} & before, before
    assert not {'/use_sim_time', '/lockstep'} & after, sorted(after)

    # No robot: the course gives up after ~tf_wait (5 wall s) and exits 1;
    # roslaunch alone would exit 0. Real time, as a user with no robot has
    # it (with /use_sim_time left true the course would give up for want of
    # /clock instead).
    failed = launch_status(graph, 'odom_out_and_back.launch')
    assert failed.returncode == 1, failed.stdout[-4000:]
    # The course's own reason, not any failure (a traceback exits 1 too),
    # in its log (ROS_LOG_DIR is the test's own tmp_path).
    logs = course_logs(tmp_path, 'odom_out_and_back')
    assert 'no transform from odom to base_footprint or base_link' in logs, logs[-4000:]
    assert 'Traceback' not in without_shutdown_races(logs), logs[-4000:]
    assert failed.stdout.rstrip().endswith(
        'launch_status: odom_out_and_back exited 1; exiting 1'), failed.stdout[-2000:]
    plain = graph.run(['roslaunch', 'rbx1_nav', 'odom_out_and_back.launch'],
                      timeout=HANG_GUARD)
    assert plain.returncode == 0 and 'REQUIRED process' in plain.stdout  # why it exists


def truth_rows(text):
    """(stamp s, x, y, yaw rad, v, w) of each whole row of a ``rostopic
    echo -p`` of a nav_msgs/Odometry topic."""
    lines = text.splitlines()
    if not lines or not lines[0].startswith('%time'):
        return []
    col = {name: i for i, name in enumerate(lines[0].split(','))}
    pose, twist = 'field.pose.pose.', 'field.twist.twist.'
    names = ['field.header.stamp', pose + 'position.x', pose + 'position.y',
             pose + 'orientation.z', pose + 'orientation.w', twist + 'linear.x',
             twist + 'angular.z']
    rows = []
    for line in lines[1:]:
        fields = line.split(',')
        if len(fields) != len(col):  # the row being written
            continue
        stamp, x, y, qz, qw, v, w = (float(fields[col[name]]) for name in names)
        rows.append((stamp * 1e-9, x, y, 2.0 * math.atan2(qz, qw), v, w))
    return rows


#: A log line of a node under simulated time: its wall and ROS stamps.
LOG_STAMPS = re.compile(r'^\[\s*INFO\s*\]\s*\[([\d.]+),\s*([\d.]+)\]:\s*(.*)$', re.M)


def following_stamp(text):
    """The ROS time (s) of the course's "Following tf" line in its output
    ``text``, None if it has none."""
    for _, stamp, message in LOG_STAMPS.findall(text):
        if message.startswith('Following tf '):
            return float(stamp)
    return None


#: The book's out-and-back (rbx1_nav.motion.course.book.OUT_AND_BACK), each
#: parameter at its default: 1 m out at 0.15 m/s, a turn of 180 deg at
#: 0.5 rad/s, the same back and again.
DEFAULT_DISTANCE, DEFAULT_SPEED, DEFAULT_TURN_SPEED = 1.0, 0.15, 0.5
#: Under lockstep the course ends where the pure model of the default
#: course does (test/helpers/course_model.py), within what
#: lockstep_max_stalled.test allows: goal_distance 0.99 left on the master
#: ended it 0.12 mm off, a goal_angle or legs left by far more.
MATCH_MM, MATCH_DEG = 0.1, 0.01
#: Simulated seconds from the course's "Following tf" line to the robot's
#: first move: its first tick after that line, the robot's step after the
#: command (0.100 s, the same every run under lockstep). A start_delay a
#: launch leaves is 2 s at 1x (20 s at 10x): it fails.
MOVE_LIMIT = 0.5
#: The farthest point within 20 mm of 1 m (a 20 Hz tick drives 7.5 mm).
DISTANCE_TOLERANCE = 0.020
#: The top speeds on the true course: within 2 % of the defaults.
SPEED_TOLERANCE = 0.02


def test_a_later_rosrun_runs_with_its_defaults(graph, tmp_path):
    # record:=true at sim_speed:=10 gives the course start_delay 20 s (2
    # wall s for rosbag at 10x): left on the master, it would hold the
    # next rosrun 20 s before it moved.
    done = launch_status(graph, 'odom_out_and_back_sim.launch', 'sim_speed:=10',
                         'record:=true', 'bag:=%s' % (tmp_path / 'course.bag'))
    assert done.returncode == 0, done.stdout[-4000:]
    assert 'start_delay 20 s' in done.stdout  # the launch did set it
    left_delay = 20.0
    names = graph.master.getParamNames()
    assert not [n for n in names if n.startswith('/odom_out_and_back/')], names

    # A plain rosrun on the fake robot under lockstep, judged by the robot's
    # ground truth. idle_speed 1: until the course joins, the robot alone
    # steps at the wall clock's pace (10x would be ten times the steps for
    # nothing).
    robot = graph.start(['roslaunch', 'rbx1_nav', 'fake_turtlebot.launch', 'sim_speed:=max',
                         'idle_speed:=1'], 'robot')
    graph.wait_for(lambda: '/fake_turtlebot' in graph.nodes(), 'robot', robot, 'robot')
    truth = graph.start(['rostopic', 'echo', '-p', '/ground_truth'], 'truth')
    graph.wait_for(lambda: truth_rows(graph.output('truth')), 'ground truth', truth, 'truth')
    course = graph.start(rosrun('rbx1_nav', 'odom_out_and_back.py'), 'course')
    try:
        status = course.wait(HANG_GUARD)
    except subprocess.TimeoutExpired:
        pytest.fail('the course still ran after %d s:\n%s' % (HANG_GUARD, graph.output('course')))
    ended = truth_rows(graph.output('truth'))[-1][0]
    # The robot at rest after the course's last stop, half a second on.
    graph.wait_for(lambda: truth_rows(graph.output('truth'))[-1][0] > ended + 0.5,
                   'ground truth after the course', truth, 'truth')
    out = graph.output('course')
    print(out)
    assert status == 0, out
    following = following_stamp(out)
    assert following is not None, out

    rows = truth_rows(graph.output('truth'))
    x0, y0, yaw0 = rows[0][1:4]
    moving = [row for row in rows if math.hypot(row[1] - x0, row[2] - y0) > 1e-4
              or abs(row[3] - yaw0) > 1e-4]
    assert moving, 'the robot never moved:\n' + out
    delay = moving[0][0] - following
    farthest = max(math.hypot(row[1] - x0, row[2] - y0) for row in rows)
    x, y, yaw = rows[-1][1:4]
    model = reference_end_pose({})
    off = 1000.0 * math.hypot(x - model.x, y - model.y)
    turn = math.degrees(math.atan2(math.sin(yaw - model.yaw), math.cos(yaw - model.yaw)))
    top_speed = max(abs(row[4]) for row in rows)
    top_turn = max(abs(row[5]) for row in rows)
    print('RESULT rosrun after the launch, by ground truth: moved %.3f simulated s after '
          'it found its robot (the left start_delay: %.0f s), farthest %.4f m (default %.1f), end '
          '%.4f mm and %+.5f deg from the pure model\'s default course, top speeds %.4f m/s '
          'and %.4f rad/s (defaults %.2f, %.1f), speed at the end %.4f, %.4f'
          % (delay, left_delay, farthest, DEFAULT_DISTANCE, off, turn, top_speed, top_turn,
             DEFAULT_SPEED, DEFAULT_TURN_SPEED, rows[-1][4], rows[-1][5]))
    # No start_delay left: it moved within MOVE_LIMIT of finding its robot,
    # in lockstep steps, whatever its start-up took.
    assert delay < MOVE_LIMIT < left_delay, out
    # Every parameter of the course at its default: 1 m out, and the
    # default course's end.
    assert abs(farthest - DEFAULT_DISTANCE) < DISTANCE_TOLERANCE, out
    assert off < MATCH_MM and abs(turn) < MATCH_DEG, out
    # linear_speed and angular_speed at theirs.
    assert abs(top_speed - DEFAULT_SPEED) < SPEED_TOLERANCE * DEFAULT_SPEED, out
    assert abs(top_turn - DEFAULT_TURN_SPEED) < SPEED_TOLERANCE * DEFAULT_TURN_SPEED, out
    assert rows[-1][4:] == (0.0, 0.0), 'the robot still moves after the course'
    # And the course says so.
    assert 'Course complete' in out, out
    assert 'odom_out_and_back: every parameter at its default' in out, out
    assert 'Starting in' not in out and 'from the parameter server' not in out, out
