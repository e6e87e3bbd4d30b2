"""The summary line a motion node logs after a course (rospy-free)."""
import math

from rbx1_nav.motion.course.command import pose_error
from rbx1_nav.transform_utils import normalize_angle


def stalls_text(stalls, odom_topic, heard):
    """How often the robot stood still while commanded to move (the course's ``stalls``);
    ``heard`` is False when nothing published on ``odom_topic``."""
    if not heard:
        return 'unknown (nothing on %s)' % odom_topic
    if stalls.count:
        return ('%d times, %.1f s in all (its watchdog, or commands late)'
                % (stalls.count, stalls.seconds))
    return 'never'


def summary_line(robot, course, final, odom_frame, tick_times, held, dropouts):
    """The 'Course complete' line; ``robot``: a fleet's namespace and ': ', else ''; ``final``:
    None without odometry; ``held``, ``dropouts``: from :func:`stalls_text`, Dropouts.summary()."""
    if final is None:
        return ('%sCourse complete in %.1f s (no odometry: final pose unknown); stood still '
                'while commanded: %s; link dropouts ridden out: %s'
                % (robot, course.elapsed, held, dropouts))
    start = course.start_pose
    mean, slowest = control_rates(tick_times)
    error, heading = pose_error(final, course.ideal_end(start))
    return (
        '%sCourse complete in %.1f s: final pose relative to start in %s: dx %+.1f mm, '
        'dy %+.1f mm, dyaw %+.2f deg; error from the ideal end pose: position %.1f mm, '
        'heading %+.2f deg; control loop %.1f Hz mean, %d Hz slowest second; stood still '
        'while commanded: %s; link dropouts ridden out: %s' % (
            robot, course.elapsed, odom_frame, 1000.0 * (final.x - start.x),
            1000.0 * (final.y - start.y), math.degrees(normalize_angle(final.yaw - start.yaw)),
            1000.0 * error, math.degrees(heading), mean, slowest, held, dropouts))


def control_rates(times):
    """(mean Hz, ticks in the slowest whole second) of control ticks at ``times`` (s, ascending);
    (0.0, 0) for fewer than two. The slowest second shows missed ticks a fine mean hides."""
    if len(times) < 2:
        return 0.0, 0
    span = times[-1] - times[0]
    mean = (len(times) - 1) / span if span > 0 else 0.0
    whole = int(span)
    if whole < 1:
        return mean, len(times)
    counts = [0] * whole
    for t in times:
        second = int(t - times[0] + 1e-6)  # a tick on a whole second is in it
        if second < whole:
            counts[second] += 1
    return mean, min(counts)
