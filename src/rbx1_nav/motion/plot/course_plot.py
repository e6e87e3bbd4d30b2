"""Plot an out-and-back run: odometry and true paths, start and end poses.

No rospy or rosbag here: rbx1_nav.motion.plot.course_plot_ros (plot_course.py) reads a bag into
:class:`Track` objects and calls :func:`plot_course`. The error shown is
the end pose against the start pose, which is what the book's course (two
legs of 1 m out and a half turn) should return to.
"""
import math

from rbx1_nav.transform_utils import normalize_angle

__all__ = ['Track', 'end_error', 'plot_course', 'describe_error',
           'final_offset', 'describe_final_offset']


class Track(object):
    """A named sequence of planar poses (x, y, yaw) in time order."""

    def __init__(self, name, poses=None):
        self.name = name
        self.poses = list(poses or [])

    def add(self, x, y, yaw):
        self.poses.append((float(x), float(y), float(yaw)))

    def __len__(self):
        return len(self.poses)

    @property
    def xs(self):
        return [p[0] for p in self.poses]

    @property
    def ys(self):
        return [p[1] for p in self.poses]

    @property
    def length(self):
        """Distance travelled along the track, in metres."""
        return sum(math.hypot(b[0] - a[0], b[1] - a[1])
                   for a, b in zip(self.poses, self.poses[1:]))


def end_error(track):
    """(position error m, heading error rad) of the last pose vs the first."""
    if not track.poses:
        raise ValueError('track %r has no poses' % track.name)
    (x0, y0, a0), (x1, y1, a1) = track.poses[0], track.poses[-1]
    return math.hypot(x1 - x0, y1 - y0), normalize_angle(a1 - a0)


def describe_error(track):
    """'odom: 3.1 mm, +0.97 deg' for a track's end-vs-start error."""
    dist, heading = end_error(track)
    return '%s: %.1f mm, %+.2f deg' % (track.name, 1000.0 * dist,
                                        math.degrees(heading))


def final_offset(track, reference):
    """Metres between the last poses of ``track`` and ``reference``.

    For a fused or odometry track against the ground truth of the same run
    (both in frames that coincide at the start, as in the simulator).
    """
    if not track.poses or not reference.poses:
        raise ValueError('final_offset needs two non-empty tracks')
    (x0, y0, _), (x1, y1, _) = track.poses[-1], reference.poses[-1]
    return math.hypot(x1 - x0, y1 - y0)


def describe_final_offset(track, reference):
    """'fused: 41.0 mm from ground truth' at the end of the run."""
    return '%s: %.1f mm from %s' % (track.name,
                                    1000.0 * final_offset(track, reference),
                                    reference.name)


def _end_distance(track):
    """Metres from the first pose of ``track`` to its last."""
    (x0, y0, _), (x1, y1, _) = track.poses[0], track.poses[-1]
    return math.hypot(x1 - x0, y1 - y0)


def _heading_arrows(ax, track, color, count=40):
    """Small arrows of the heading at ``count`` points of the track, so the
    legs (out and back overlap) and the turns (arrows fanning out) show."""
    step = max(1, len(track.poses) // count)
    sample = track.poses[::step]
    ax.quiver([p[0] for p in sample], [p[1] for p in sample],
              [math.cos(p[2]) for p in sample], [math.sin(p[2]) for p in sample],
              color=color, alpha=0.6, width=0.004, scale=30, zorder=3)


def _pose_arrow(ax, pose, color, label, length=0.12):
    x, y, yaw = pose
    ax.annotate('', xy=(x + length * math.cos(yaw), y + length * math.sin(yaw)),
                xytext=(x, y),
                arrowprops=dict(arrowstyle='->', color=color, lw=2))
    ax.plot([x], [y], marker='o' if label == 'start' else 's', color=color,
            markersize=7, linestyle='none')


def plot_course(tracks, path, title=None, reference=None):
    """Draw every non-empty track with start/end poses; save a PNG to path.

    Returns the title used (first line: the course, second: the errors;
    with a ``reference`` track, such as the ground truth, a third line: each
    other track's final distance from it), which the PNG holds as its Title.
    """
    import matplotlib
    matplotlib.use('Agg')
    import matplotlib.pyplot as plt

    tracks = [t for t in tracks if len(t)]
    if not tracks:
        raise ValueError('nothing to plot: every track is empty')
    # Wide solid first, thin dashed over it: identical paths stay visible.
    styles = [('tab:red', 4.0, '-'), ('tab:blue', 1.5, '--'),
              ('tab:green', 1.5, ':'), ('tab:purple', 1.0, '-.')]
    fig, ax = plt.subplots(figsize=(9, 6))
    # The start/end region, magnified: where the course's error shows.
    zoom = ax.inset_axes([0.62, 0.52, 0.36, 0.44])
    x0, y0, _ = tracks[0].poses[0]
    half = max(0.02, 1.5 * max(_end_distance(t) for t in tracks))
    for track, (color, width, line) in zip(tracks, styles):
        label = '%s: %.2f m travelled; %s from the start' % (
            track.name, track.length, describe_error(track).split(': ', 1)[1])
        for axes in (ax, zoom):
            axes.plot(track.xs, track.ys, color=color, lw=width,
                      linestyle=line, alpha=0.8,
                      label=label if axes is ax else None)
            _pose_arrow(axes, track.poses[0], color, 'start', 0.3 * half)
            _pose_arrow(axes, track.poses[-1], color, 'end', 0.3 * half)
        _heading_arrows(ax, track, color)
    zoom.set_xlim(x0 - half, x0 + half)
    zoom.set_ylim(y0 - half, y0 + half)
    zoom.set_aspect('equal', adjustable='box')
    zoom.tick_params(labelsize=7)
    zoom.set_title('start and end, %.0f mm across' % (2000 * half), fontsize=8)
    ax.indicate_inset_zoom(zoom, edgecolor='grey')
    ax.plot([], [], 'ko', label='start pose')
    ax.plot([], [], 'ks', label='end pose')
    ax.plot([], [], color='grey', marker=r'$\rightarrow$', linestyle='none',
            markersize=10, label='heading along the way')
    full_title = '%s\nend vs start: %s' % (
        title or 'Out and back', '; '.join(describe_error(t) for t in tracks))
    others = [t for t in tracks if reference is not None and t is not reference]
    if reference is not None and len(reference) and others:
        full_title += '\nat the end: %s' % '; '.join(
            describe_final_offset(t, reference) for t in others)
    ax.set_title(full_title, fontsize=10)
    ax.set_xlabel('x (m)')
    ax.set_ylabel('y (m)')
    ax.set_aspect('equal', adjustable='datalim')
    ax.margins(0.15)
    ax.grid(True, alpha=0.3)
    ax.legend(loc='best', fontsize=8)
    fig.tight_layout()
    # The title in the PNG's text too: its numbers read without the picture.
    fig.savefig(path, dpi=100, metadata={'Title': full_title})
    plt.close(fig)
    return full_title
