"""The list- and name-valued checks the simulators and umbmark declare, kept out of
rbx1_nav.common.params so that a course does not load them. No rospy here.
"""
import re

from rbx1_nav.common.params import number, text
from rbx1_nav.transform_utils import strip_leading_slash

__all__ = ['number_list', 'pairs', 'names', 'texts']


def number_list(name, value, length, minimum=None, maximum=None, allow_zero=True):
    """``value`` as a list of ``length`` floats, each checked like :func:`number`."""
    if not isinstance(value, (list, tuple)) or len(value) != length:
        raise ValueError('%s must be a list of %d numbers, got %.200r' % (name, length, value))
    return [number('%s[%d]' % (name, i), item, minimum, maximum, allow_zero)
            for i, item in enumerate(value)]


def pairs(name, value):
    """``value`` as a list of (x, y) pairs of finite floats; '' or [] is none."""
    if isinstance(value, str) and not value.strip():
        return []
    problem = '%s must be a list of [x, y] pairs of numbers, got %.200r' % (name, value)
    if not isinstance(value, (list, tuple)):
        raise ValueError(problem)
    result = []
    for k, item in enumerate(value):
        if not isinstance(item, (list, tuple)) or len(item) != 2:
            raise ValueError(problem)
        result.append(tuple(number('%s[%d]' % (name, k), v) for v in item))
    return result


def texts(name, value):
    """``value`` as a list of non-empty texts: a list of them, or one text
    of them separated by spaces ('' or None: none)."""
    if isinstance(value, list):
        return [text(name, item) for item in value]
    return text(name, value, allow_empty=True).split()


# A relative ROS graph name: base names joined by '/'.
_RELATIVE_NAME = re.compile(r'[A-Za-z][A-Za-z0-9_]*(/[A-Za-z][A-Za-z0-9_]*)*$')


def names(name, value, maximum=None):
    """``value`` as a non-empty list of distinct relative ROS names (namespaces)."""
    if not isinstance(value, (list, tuple)) or not value:
        raise ValueError('%s must be a non-empty list of names such as '
                         '[robot1, robot2], got %.200r' % (name, value))
    if maximum is not None and len(value) > maximum:
        raise ValueError('%s must hold at most %d names, got %d' % (name, maximum, len(value)))
    result = []
    for k, item in enumerate(value):
        item = strip_leading_slash(item.strip()) if isinstance(item, str) else item
        if not isinstance(item, str) or not _RELATIVE_NAME.match(item):
            raise ValueError('%s[%d] must be a ROS name (letters, digits, _ and /, starting with '
                             'a letter), got %.200r' % (name, k, value[k]))
        if item in result:
            raise ValueError('%s names %r twice' % (name, item))
        result.append(item)
    return result
