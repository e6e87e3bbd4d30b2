"""The graphs the bench starts: one course on a master of its own, as a
user starts it (:class:`Graph`, :func:`course`), and a master that this
process joins for many runs (:class:`Master`).

A course's final error is read from the simulator's ``ground_truth``
after it: the robot starts at the origin, and the out-and-back course
ends where it began.
"""
import math
import os
import re
import subprocess
import time

import yaml

from common import (cpu_by_name, end_processes, free_port, ground_truth, processes,
                    wait_for_master)

SUMMARY = re.compile(r'Course complete in ([\d.]+) s')
#: Clock speed (x real time) for courses that follow pose_ekf, which is no
#: lockstep member.
POSE_EKF_SPEED = '5'


class Graph(object):
    """A master, a launch file and the processes they start (one run)."""

    def __init__(self, launch, args, env=None):
        self.env = dict(env or os.environ, ROS_MASTER_URI='http://localhost:%d' % free_port())
        self.env.pop('ROS_NAMESPACE', None)
        self.env['PYTHONUNBUFFERED'] = '1'  # lines arrive (and are timed) as logged
        port = self.env['ROS_MASTER_URI'].rsplit(':', 1)[1]
        self.launch = subprocess.Popen(
            ['roslaunch', '-p', port, 'rbx1_nav', launch]
            + ['%s:=%s' % kv for kv in sorted(args.items())],
            env=self.env, stdout=subprocess.DEVNULL, stderr=subprocess.STDOUT,
            start_new_session=True)
        self.procs = [self.launch]

    def run(self, script, params, wall_limit):
        """Run a course node to its end; return its lines and timings."""
        cmd = ['rosrun', 'rbx1_nav', script] + [
            '_%s:=%s' % kv for kv in sorted(params.items())]
        proc = subprocess.Popen(cmd, env=self.env, stdout=subprocess.PIPE,
                                stderr=subprocess.STDOUT, universal_newlines=True,
                                start_new_session=True)
        self.procs.append(proc)
        lines, started, ended, cpu_start = [], None, None, None
        deadline = time.monotonic() + wall_limit
        for line in proc.stdout:
            lines.append(line.rstrip())
            if started is None and 'Following tf' in line:
                started, cpu_start = time.monotonic(), self.cpu()
            if SUMMARY.search(line):
                ended, cpu_end = time.monotonic(), self.cpu()
            if time.monotonic() > deadline:
                proc.kill()
                break
        proc.wait()
        result = dict(status=proc.returncode, output=lines[-5:])
        match = next((SUMMARY.search(l) for l in lines if SUMMARY.search(l)), None)
        if match and started is not None:
            result.update(sim_s=float(match.group(1)), wall_s=ended - started,
                          cpu={name: cpu_end.get(name, 0.0) - cpu_start.get(name, 0.0)
                               for name in cpu_end})
        return result

    def cpu(self):
        """{node name: CPU seconds so far} over the run's processes."""
        names = {}
        for proc in self.procs:
            names.update(processes(proc.pid))
        return cpu_by_name(names)

    def truth(self, topic='ground_truth'):
        """(x, y, yaw) of the simulator's next ground_truth message."""
        return ground_truth(self.env, topic)

    def close(self):
        end_processes(self.procs, 15)


def course(setup='ideal', mode='default', speed='max', lockstep=True, seed=None,
           physics=False, env=None):
    """One out-and-back course; a result dict (errors on ground truth).
    ``env``: the environment of another workspace (speed.courses.sourced)."""
    launch = 'fake_turtlebot_ekf.launch' if setup == 'pose_ekf' else 'fake_turtlebot.launch'
    if setup == 'pose_ekf' and speed == 'max':
        # pose_ekf is no lockstep member: at full speed it falls behind the
        # clock and the course aborts on its stale tf (as in the rostests).
        speed = POSE_EKF_SPEED
    args = dict(sim_speed=speed, model='false')
    if physics:
        args['physics'] = 'true'
    if setup != 'pose_ekf':
        args.update(lockstep=lockstep, realistic=setup == 'realistic')
    if seed is not None and setup != 'ideal':
        args['seed'] = seed
    graph = Graph(launch, args, env)
    try:
        # roslaunch sets /use_sim_time just after its master is up: a course
        # started before that runs on the wall clock against the simulator's
        # stamps and never ends. /clock flowing means the parameter is set.
        clock(graph)
        params = {'precise': mode == 'precise', 'tf_wait': 30.0}
        if not lockstep:  # a node behind the clock must not abort
            params['tf_timeout'] = 5.0
        result = graph.run('odom_out_and_back.py', params, wall_limit=600)
        if result['status'] == 0:
            x, y, yaw = graph.truth()
            result.update(error_mm=1000.0 * math.hypot(x, y),
                          heading_deg=math.degrees(yaw))
    finally:
        graph.close()
    result.update(setup=setup, mode=mode, speed=speed, lockstep=lockstep, seed=seed)
    return result


def clock(graph, wall_limit=60.0):
    """The simulated seconds of the next /clock message (waiting for the
    master and the clock to come up)."""
    deadline = time.monotonic() + wall_limit
    while True:
        out = subprocess.run(['rostopic', 'echo', '-n', '1', '/clock/clock'],
                             env=graph.env, stdout=subprocess.PIPE,
                             stderr=subprocess.DEVNULL, universal_newlines=True,
                             timeout=wall_limit).stdout
        stamp = yaml.safe_load(out.split('---')[0])
        if stamp:
            return stamp['secs'] + 1e-9 * stamp['nsecs']
        if time.monotonic() > deadline:
            raise RuntimeError('no /clock within %.0f s' % wall_limit)
        time.sleep(0.5)


def describe(result):
    """One line on a :func:`course` result."""
    if 'error_mm' not in result:
        return 'FAILED (exit %s): %s' % (result['status'], ' | '.join(result['output']))
    return '%.1f mm, %+.2f deg, %.1f s sim in %.1f s wall' % (
        result['error_mm'], result['heading_deg'], result['sim_s'], result['wall_s'])


class Master(object):
    """One roscore (a free port) and a rospy node in this process, for many
    runs: rospy joins one master per process."""

    def __init__(self):
        self.port = free_port()
        self.env = dict(os.environ, ROS_MASTER_URI='http://localhost:%d' % self.port)
        os.environ.update(self.env)
        self.core = subprocess.Popen(['roscore', '-p', str(self.port)], env=self.env,
                                     stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL,
                                     start_new_session=True)
        import rospy
        from nav_msgs.msg import Odometry
        self.rospy, self.Odometry = rospy, Odometry
        wait_for_master(self.env['ROS_MASTER_URI'], self.core)
        rospy.init_node('bench_fleet_scale', disable_signals=True)

    def close(self):
        self.rospy.signal_shutdown('bench done')
        end_processes([self.core], 30)
