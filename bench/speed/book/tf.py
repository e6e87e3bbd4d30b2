"""A stand-in for tf1's Python ``tf`` module, just what the book's
odom_out_and_back.py uses (bench/speed/book: Debian 12 has no Python tf).

Noetic's own ``tf.TransformListener`` is a tf2_ros.Buffer filled by a
Python subscriber on /tf and /tf_static; so is this one
(tf2_ros.TransformListener), with tf1's leading-slash frame names
stripped and its exceptions being tf2's, as in Noetic's tf.
"""
import tf2_ros

Exception = tf2_ros.TransformException  # noqa: A001 (tf1's name)
LookupException = tf2_ros.LookupException
ConnectivityException = tf2_ros.ConnectivityException
ExtrapolationException = tf2_ros.ExtrapolationException


def _frame(name):
    return name[1:] if name.startswith('/') else name


class TransformListener(object):
    """tf1's listener: waitForTransform and lookupTransform."""

    def __init__(self):
        self._buffer = tf2_ros.Buffer()
        self._listener = tf2_ros.TransformListener(self._buffer)

    def waitForTransform(self, target_frame, source_frame, time, timeout):
        if not self._buffer.can_transform(_frame(target_frame), _frame(source_frame),
                                          time, timeout):
            raise Exception('no transform %s -> %s within %s s'
                            % (target_frame, source_frame, timeout.to_sec()))

    def lookupTransform(self, target_frame, source_frame, time):
        """([x, y, z], [x, y, z, w]), as tf1 returns them."""
        msg = self._buffer.lookup_transform(_frame(target_frame), _frame(source_frame),
                                            time)
        t, r = msg.transform.translation, msg.transform.rotation
        return [t.x, t.y, t.z], [r.x, r.y, r.z, r.w]
