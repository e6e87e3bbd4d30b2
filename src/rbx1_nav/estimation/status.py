"""The texts pose_ekf shows a person: its start-up line (what it listens
to and publishes), its status (the node's ``~get_status``), the warning for
a used sensor that never sent anything, and the error while another node
publishes the same transform (rbx1_nav.common.tf_publishers.OtherPublisherWatch
spots it). No rospy here.
"""
import numpy as np

from rbx1_nav.common.tf_publishers import OtherPublisherWatch
from rbx1_nav.estimation.sensors import MOTION_SOURCES, SENSORS

__all__ = ['state_text', 'status_text', 'listening_text', 'output_text',
           'silent_sensor_text', 'OtherPublisherWatch', 'other_publisher_text',
           'SENSOR_KINDS']

#: What each sensor measures, for the status text.
SENSOR_KINDS = {'odom': 'wheel odometry, relative pose',
                'imu': 'gyro yaw, relative',
                'vo': 'visual odometry, relative pose',
                'gps': 'absolute x, y in the output frame'}
#: What the IMU measures in GPS mode (gps_used).
IMU_KIND_GPS = 'IMU yaw, absolute while GPS is active'


def state_text(fusion):
    """``fusion``'s state: 'waiting for odom, imu', 'running' or
    'running; dropped: imu'."""
    used = fusion.used_sensors()
    if fusion.ekf is None:
        source = ('imu and gps' if fusion.gps_used else
                  next((n for n in MOTION_SOURCES if fusion.used(n)), 'imu'))
        missing = [n for n in used if not fusion.watches[n].active]
        return 'waiting for %s to start (no data yet from: %s)' % (
            source, ', '.join(missing) or 'none')
    dropped = [n for n in used if fusion.watches[n].ever_active
               and not fusion.watches[n].active]
    waiting = [n for n in used if not fusion.watches[n].ever_active]
    text = 'running'
    if dropped:
        text += '; dropped: ' + ', '.join(dropped)
    if waiting:
        text += '; never received: ' + ', '.join(waiting)
    return text


def status_text(fusion, now, topics=None):
    """``fusion``'s status for a person: state, each sensor, the estimate.

    ``topics`` maps sensor names to the topics they are read from.
    """
    topics = topics or {}
    lines = ['state: ' + state_text(fusion)]
    for name in SENSORS:
        where = ' on %s' % topics[name] if name in topics else ''
        if not fusion.used(name):
            lines.append('%s%s: not used' % (name, where))
            continue
        watch = fusion.watches[name]
        kind = (IMU_KIND_GPS if name == 'imu' and fusion.gps_used
                else SENSOR_KINDS[name])
        line = '%s%s (%s): %s' % (name, where, kind, watch.describe(now))
        if watch.last_seen is not None:
            line += ', last stamp %.3f, received %.2f s ago' % (
                watch.last_stamp if watch.last_stamp is not None
                else float('nan'), now - watch.last_seen)
        lines.append(line)
    if fusion.ekf is None:
        lines.append('estimate: none yet')
    else:
        x, y, yaw = fusion.ekf.pose
        lines.append('estimate at stamp %.3f: x=%.3f m y=%.3f m yaw=%.4f '
                     'rad' % (fusion.stamp, x, y, yaw))
        lines.append('covariance (x, y, yaw): %s' % _matrix_text(
            fusion.ekf.cov))
        if fusion.ekf.rotation is not None:
            rotation, variance = fusion.ekf.rotation
            lines.append('GPS frame rotation: the heading in it is the '
                         "IMU's %+.2f deg (sd %.2f deg)" % (
                             np.degrees(rotation), np.degrees(np.sqrt(variance))))
    lines.append('sensor_timeout %.3g s; filter restarts: %d'
                 % (fusion.sensor_timeout, fusion.restarts))
    return '\n'.join(lines)


def listening_text(topics, output_topic, output_frame, base_frame,
                   publish_tf):
    """The start-up line: the sensors' ``topics`` (name -> resolved topic)
    and what the node publishes (``output_topic`` and, with
    ``publish_tf``, the tf ``output_frame -> base_frame``)."""
    return 'listening on %s; publishing %s%s' % (
        ', '.join('%s %s' % item for item in sorted(topics.items())),
        output_topic, ' and tf %s -> %s' % (output_frame, base_frame)
        if publish_tf else ' only (~publish_tf false: no tf)')


def output_text(output_topic, output_frame, base_frame, publish_tf, others):
    """The status lines on the node's output: its topic, its tf, and the
    ``others`` (node names) heard publishing ``base_frame`` on tf."""
    text = 'output: %s, tf %s' % (
        output_topic, '%s -> %s' % (output_frame, base_frame) if publish_tf
        else 'off (~publish_tf false)')
    if others:
        text += '\nalso publishing %s on tf: %s' % (base_frame,
                                                    ', '.join(others))
    return text


def _matrix_text(matrix):
    return '[' + '; '.join(' '.join('%.3g' % v for v in row)
                           for row in np.asarray(matrix)) + ']'


def silent_sensor_text(name, topic, timeout, publishers, rejected=None):
    """The warning for a used sensor that never sent a message the filter took.

    ``publishers`` lists the nodes that publish ``topic`` (the node's
    subscriber is connected to them), or is None when that is unknown;
    ``rejected``: (how many readings were dropped, the last one's
    RejectedInput), or None if none came.
    """
    if rejected is not None:
        count, last = rejected
        return ('%s_used is true but every reading on %s in the %.3g s since '
                'start-up was dropped (%d so far, the last as %s: %s): fix %s' % (
                    name, topic, timeout, count, last.kind, last.detail,
                    '%s, which publishes it' % ', '.join(sorted(publishers))
                    if publishers else 'the node that publishes it'))
    text = ('%s_used is true but no message came on %s within %.3g s of '
            'start-up; ' % (name, topic, timeout))
    if publishers is None:
        return text + 'whether anything publishes it is unknown'
    if not publishers:
        return text + ('nothing publishes %s: start the driver, or remap '
                       '%s to the topic it publishes, or set ~%s_used false'
                       % (topic, name if name != 'imu' else 'imu_data', name))
    return text + ('%s publishes it but sent nothing: check that node (a '
                   'sensor not yet started? a wrong message type?)'
                   % ', '.join(sorted(publishers)))


def other_publisher_text(caller, parent, child, topic):
    """The error logged while another node publishes our transform."""
    return ('node %s also publishes the transform %s -> %s on %s; with two '
            'publishers the robot\'s pose jumps between them. Fix: turn off '
            'that node\'s tf (a TurtleBot driver or fake_turtlebot: '
            'publish_tf: false), or give pose_ekf other frames '
            '(~output_frame, ~base_footprint_frame), or run pose_ekf as an '
            'estimator only (~publish_tf false)' % (caller, parent, child,
                                                     topic))
