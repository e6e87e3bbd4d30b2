"""The parameters every motion node shares, the runner's own (no rospy)."""
from rbx1_nav.common import params
from rbx1_nav.common.params import param
from rbx1_nav.motion.course.settle import SETTLE_PARAMS

__all__ = ['common_params']


def common_params(rate):
    """The runner's own parameters; ``rate`` (Hz) is the node's default."""
    return (
        param('rate', float(rate), params.number, 'Hz', 'control rate',
              minimum=1.0, maximum=1000.0),
        param('odom_frame', 'odom', params.frame, '', 'odometry frame'),
        param('base_frame', '', params.frame, '',
              "robot frame; '' tries base_footprint, then base_link", allow_empty=True),
        param('tf_wait', 5.0, params.number, 's',
              'wait this long for /clock, the first transform and a cmd_vel subscriber',
              **params.POSITIVE),
        param('tf_timeout', 1.0, params.number, 's',
              'stop the robot when the transform is older than this', **params.POSITIVE),
        param('link_grace', 5.0, params.number, 's',
              'then wait this much longer for it (a Wi-Fi dropout) before giving up',
              minimum=0.0, maximum=600.0),
        param('max_tf_age', 0.1, params.number, 's',
              'warn when the transform steered by is older than this (a slow link to the robot)',
              **params.POSITIVE),
        param('start_delay', 0.0, params.number, 's',
              'pause before moving (e.g. for a bag recorder)', minimum=0.0),
    ) + SETTLE_PARAMS
