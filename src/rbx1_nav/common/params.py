"""Checks for ROS parameter values, shared by every node of the package.

A node reads a raw value with ``rospy.get_param`` and passes it, with the
parameter's name, to one of these functions. Each returns the value in the
type the node needs or raises ValueError with a message that names the
parameter, so the node can log one clear line and exit. No rospy here.

Parameter servers are loose about types: YAML 1.1 (rosparam) reads ``1e6``
as a string, and ``_publish_tf:=false`` on a command line or ``value="false"``
in a launch file arrive as booleans, but a quoted ``'false'`` arrives as a
string. So numbers are accepted as numeric strings too, and flags as the
strings 'true' / 'false'; bools are never numbers and numbers never flags.
An error quotes at most 200 characters of a bad value.
"""
import difflib
import math
import numbers
import re
from collections import namedtuple

from rbx1_nav.transform_utils import strip_leading_slash

__all__ = ['number', 'integer', 'flag', 'frame', 'text', 'number_list', 'pairs',
           'names', 'raw', 'POSITIVE', 'Param', 'param', 'read_all', 'describe', 'unknown',
           'bounds', 'clear_text', 'check_all', 'unit_text', 'UNIT_NAMES', 'start_text',
           'command_line', 'leftovers', 'typos']


def _as_float(name, value):
    """``value`` as a float: a real number or a numeric string, not a bool."""
    if isinstance(value, bool) or not isinstance(value, (numbers.Real, str)):
        raise ValueError('%s must be a number, got %.200r' % (name, value))
    try:
        return float(value.strip() if isinstance(value, str) else value)
    except (ValueError, OverflowError):
        raise ValueError('%s must be a number, got %.200r' % (name, value))


def _range_text(minimum, maximum, allow_zero):
    """'>= 0 and <= 5', '> 0', ... for an error message."""
    parts = []
    if minimum is not None:
        exclusive = minimum == 0 and not allow_zero
        parts.append('%s %g' % ('>' if exclusive else '>=', minimum))
    zero_in_range = ((minimum is None or minimum < 0)
                     and (maximum is None or maximum > 0))
    if not allow_zero and zero_in_range:
        parts.append('!= 0')
    if maximum is not None:
        parts.append('<= %g' % maximum)
    return ' and '.join(parts)


def number(name, value, minimum=None, maximum=None, allow_zero=True):
    """``value`` as a finite float within ``[minimum, maximum]``.

    Accepts ints, floats and numeric strings ('1e6'); rejects bools, NaN,
    infinity, values outside the bounds (both inclusive; None = unbounded)
    and, if ``allow_zero`` is false, zero: ``minimum=0, allow_zero=False``
    means "> 0".
    """
    result = _as_float(name, value)
    if not math.isfinite(result):
        raise ValueError('%s must be a finite number, got %.200r' % (name, value))
    if ((minimum is not None and result < minimum)
            or (maximum is not None and result > maximum)
            or (not allow_zero and result == 0.0)):
        raise ValueError('%s must be %s, got %.200r' % (
            name, _range_text(minimum, maximum, allow_zero), value))
    return result


def integer(name, value, minimum=None, maximum=None):
    """``value`` as an int within ``[minimum, maximum]``.

    Accepts ints, integral floats (3.0) and strings of either ('3', '1e3');
    rejects bools, fractions, NaN and infinity.
    """
    if isinstance(value, int) and not isinstance(value, bool):
        result = value
    else:
        as_float = _as_float(name, value)
        if not (math.isfinite(as_float) and as_float.is_integer()):
            raise ValueError('%s must be an integer, got %.200r' % (name, value))
        result = int(as_float)
    if ((minimum is not None and result < minimum)
            or (maximum is not None and result > maximum)):
        raise ValueError('%s must be an integer %s, got %.200r' % (
            name, _range_text(minimum, maximum, True), value))
    return result


def flag(name, value):
    """``value`` as a bool: a bool, or the string 'true' or 'false' (any case).

    Anything else (numbers, 'yes', '') is a ValueError rather than a guess:
    ``bool('false')`` is True, which is how flags silently misbehave.
    """
    if isinstance(value, bool):
        return value
    if isinstance(value, str) and value.strip().lower() in ('true', 'false'):
        return value.strip().lower() == 'true'
    raise ValueError('%s must be true or false, got %.200r' % (name, value))


def raw(name, value, **options):
    """``value`` as given, for a parameter another module checks;
    ``options`` are that module's bounds, kept for --help and the docs."""
    return value


def text(name, value, allow_empty=False):
    """``value`` as a string with surrounding whitespace removed. Where
    empty is allowed, None is empty too: ``_plot:=`` on a command line
    sets YAML's empty value, None."""
    if value is None and allow_empty:
        return ''
    if not isinstance(value, str):
        raise ValueError('%s must be a string, got %.200r' % (name, value))
    result = value.strip()
    if not result and not allow_empty:
        raise ValueError('%s must not be empty' % name)
    return result


def frame(name, value, allow_empty=False):
    """``value`` as a tf2 frame id: a string, whitespace and leading '/' removed.

    A frame id with whitespace inside is a ValueError, and so is an empty
    one unless ``allow_empty`` (for parameters where empty means
    "automatic" or "from the input").
    """
    result = strip_leading_slash(text(name, value, allow_empty=True))
    if any(c.isspace() for c in result):
        raise ValueError('%s must be a frame id without spaces, got %.200r'
                         % (name, value))
    if not result and not allow_empty:
        raise ValueError('%s must name a frame, got %.200r' % (name, value))
    return result


def number_list(name, value, length, minimum=None, maximum=None,
                allow_zero=True):
    """``value`` as a list of ``length`` floats, each checked like :func:`number`."""
    if not isinstance(value, (list, tuple)) or len(value) != length:
        raise ValueError('%s must be a list of %d numbers, got %.200r'
                         % (name, length, value))
    return [number('%s[%d]' % (name, i), item, minimum, maximum, allow_zero)
            for i, item in enumerate(value)]


def pairs(name, value):
    """``value`` as a list of (x, y) float pairs; '' or [] is no pairs.

    Each pair must be two finite numbers; the message quotes at most 200
    characters of a bad value.
    """
    if isinstance(value, str) and not value.strip():
        return []
    problem = '%s must be a list of [x, y] pairs of numbers, got %.200r' % (
        name, value)
    if not isinstance(value, (list, tuple)):
        raise ValueError(problem)
    result = []
    for k, item in enumerate(value):
        if not isinstance(item, (list, tuple)) or len(item) != 2:
            raise ValueError(problem)
        result.append(tuple(number('%s[%d]' % (name, k), v) for v in item))
    return result


# A relative ROS graph name: base names (a letter, then letters, digits and
# underscores) joined by '/'.
_RELATIVE_NAME = re.compile(r'[A-Za-z][A-Za-z0-9_]*(/[A-Za-z][A-Za-z0-9_]*)*$')


def names(name, value, maximum=None):
    """``value`` as a list of distinct relative ROS names (namespaces).

    A leading '/' is dropped, as for frames; an empty list, a name that is
    not a legal ROS name ('robot 1', '1robot', 'a//b') or a repeated one is
    a ValueError, and so are more than ``maximum`` names.
    """
    if not isinstance(value, (list, tuple)) or not value:
        raise ValueError('%s must be a non-empty list of names such as '
                         '[robot1, robot2], got %.200r' % (name, value))
    if maximum is not None and len(value) > maximum:
        raise ValueError('%s must hold at most %d names, got %d'
                         % (name, maximum, len(value)))
    result = []
    for k, item in enumerate(value):
        item = strip_leading_slash(item.strip()) if isinstance(item, str) else item
        if not isinstance(item, str) or not _RELATIVE_NAME.match(item):
            raise ValueError('%s[%d] must be a ROS name (letters, digits, _ '
                             'and /, starting with a letter), got %.200r'
                             % (name, k, value[k]))
        if item in result:
            raise ValueError('%s names %r twice' % (name, item))
        result.append(item)
    return result


# Options for a number that must be greater than zero: number(..., **POSITIVE).
POSITIVE = dict(minimum=0.0, allow_zero=False)


Param = namedtuple('Param', 'name default check options unit doc note')
Param.__doc__ = """One private parameter of a node, declared once.

``check`` is one of this module's functions and ``options`` its keyword
arguments (bounds); ``unit`` and ``doc`` are for the start-up log line and
the documentation; ``note`` goes with the unit into an error about the
value (where a twin node or the book takes another unit, say so).
"""

#: Units as an error message spells them out.
UNIT_NAMES = {'m': 'metres', 'm/s': 'metres per second', 'rad': 'radians',
              'rad/s': 'radians per second', 'deg': 'degrees', 's': 'seconds',
              'Hz': 'hertz'}


def param(name, default, check, unit='', doc='', note='', **options):
    """A :class:`Param`; keyword arguments beyond ``note`` go to ``check``."""
    return Param(name, default, check, options, unit, doc, note)


def unit_text(spec, value):
    """What an error about ``spec``'s ``value`` adds: ' (in radians; its
    note; 180 deg is 3.14159 rad)', or '' for a parameter without a unit.
    A value out of range in radians is most likely degrees: converted."""
    if not spec.unit:
        return ''
    parts = ['in %s' % UNIT_NAMES.get(spec.unit, spec.unit)]
    if spec.note:
        parts.append(spec.note)
    if spec.unit == 'rad':
        try:
            degrees = float(value)
        except (TypeError, ValueError, OverflowError):
            degrees = float('nan')
        if math.isfinite(degrees) and not isinstance(value, bool):
            parts.append('%g deg is %g rad' % (degrees, math.radians(degrees)))
    return ' (%s)' % '; '.join(parts)


def read_all(specs, lookup, prefix=''):
    """Check every parameter of ``specs``; return (values by name, problems).

    ``lookup(name, default)`` gives a parameter's raw value (for a node,
    ``rospy.get_param('~' + name, default)``); ``prefix`` goes before each
    name in the messages. A problem leaves the default in ``values``.
    """
    values, problems = {}, []
    for spec in specs:
        value = lookup(spec.name, spec.default)
        try:
            values[spec.name] = spec.check(prefix + spec.name, value,
                                           **spec.options)
        except ValueError as err:
            problems.append(str(err) + unit_text(spec, value))
            values[spec.name] = spec.default
    return values, problems


def clear_text(node_name, names):
    """How to clear the parameters ``names`` of the node ``node_name``
    (``/nav_square``) from the parameter server, one command each."""
    return ('A value given as _name:=value stays on the parameter server for '
            'later runs: clear it with %s' % '; '.join(
                'rosparam delete %s/%s' % (node_name.rstrip('/'), name)
                for name in names))


def check_all(specs, lookup, node_name):
    """The checked values of a node's private parameters ``specs``.

    ``lookup`` as for :func:`read_all`. Raises ValueError naming every
    unusable value, then the ``rosparam delete`` that clears each of them
    from the parameter server of the node ``node_name``.
    """
    values, problems = read_all(specs, lookup, '~')
    if problems:
        bad = [spec.name for spec in specs if read_all([spec], lookup)[1]]
        raise ValueError('%s. %s' % ('; '.join(problems),
                                     clear_text(node_name, bad)))
    return values


def _shown(value, spec):
    """A value as a start-up line, --help and the docs show it. None reads
    as its check's ``none_text`` ('max' for a clock speed), else 'none'."""
    if value is None:
        return getattr(spec.check, 'none_text', 'none')
    if isinstance(value, bool):
        return 'on' if value else 'off'
    if isinstance(value, float):
        return '%g' % value
    return repr(value) if value == '' else str(value)


def describe(specs, values):
    """'name value unit, ...' for a start-up log line."""
    return ', '.join(('%s %s %s' % (s.name, _shown(values[s.name], s), s.unit)).strip()
                     for s in specs)


def start_text(specs, values):
    """A node's start-up line: the parameters whose values differ from
    their defaults (:func:`describe`), the others summed up."""
    changed = [spec for spec in specs if values[spec.name] != spec.default]
    if not changed:
        return 'every parameter at its default (--help lists them)'
    return '%s; every other parameter at its default (--help lists them)' % (
        describe(changed, values))


def unknown(given, specs):
    """[(name, nearest known name or None)] for names in ``given`` that no
    spec declares: typos such as ``_goal_distnace:=2``."""
    known = [spec.name for spec in specs]
    return [(name, (difflib.get_close_matches(name, known, n=1) or [None])[0])
            for name in sorted(given) if name not in known]


def command_line(argv):
    """(names given as ``_name:=value`` in ``argv``, whether roslaunch
    started the node).

    roslaunch gives every node it starts a ``__log:=`` argument; rosrun
    passes only what the user typed.
    """
    given, launched = set(), False
    for arg in argv[1:]:
        name, sep, _ = arg.partition(':=')
        if not sep:
            continue
        if name == '__log':
            launched = True
        elif name.startswith('_') and not name.startswith('__'):
            given.add(name[1:])
    return given, launched


def typos(found, argv):
    """The ``found`` unknown parameters ((name, nearest) pairs, from
    :func:`unknown`) that stop a node, and why, as a line; None when there
    are none.

    One given on the command line (``_goal_distnace:=0.5``) is a typo the
    node must not run past: it would drive the default. So is any under
    roslaunch (``argv`` has ``__log:=``): every launch file of the package
    starts its nodes with clear_params, so each private parameter is the
    launch file's own ``<param>``. Otherwise (rosrun) an unknown parameter
    not on the command line is a leftover on the master, and only warned
    of.
    """
    given, launched = command_line(argv)
    bad = [(name, nearest) for name, nearest in found
           if launched or name in given]
    if not bad:
        return None
    return ('unknown parameter%s %s %s; not starting, so a misspelt name '
            'does not run on its default. Fix the name (--help lists them)' % (
                's' * (len(bad) > 1),
                ', '.join('~%s%s' % (name, ' (did you mean ~%s?)' % nearest
                                     if nearest else '') for name, nearest in bad),
                'in the launch file' if launched else 'on the command line'))


def leftovers(specs, values, argv, node_name):
    """A line naming the parameters a node did not get from its own
    command line or launch file, or None.

    Every launch file of the package starts its nodes with clear_params, so
    under roslaunch (``argv`` has ``__log:=``) the node's private parameters
    are the launch file's own. Started otherwise (rosrun), a value that
    differs from its default and is not a ``_name:=value`` of ``argv`` was
    on the parameter server already: left by an earlier run on this master
    (the parameter server keeps ``_name:=value``, a launch file's params
    and dynamic_reconfigure's settings until the master ends) or set by
    hand with rosparam. ``node_name`` is the node's resolved name
    (``/calibrate_linear``), whose namespace ``rosparam delete`` clears.
    """
    given, launched = command_line(argv)
    if launched:
        return None
    old = [spec for spec in specs
           if spec.name not in given and values[spec.name] != spec.default]
    if not old:
        return None
    return ('from the parameter server, not this command line (an earlier '
            'run on this master, or rosparam set): %s; `rosparam delete %s` '
            'to start clean' % (describe(old, values), node_name))


def bounds(spec):
    """A spec's bounds as its error message gives them ('> 0 and <= 2'),
    or '' when it has none."""
    options = spec.options
    if ('minimum' not in options and 'maximum' not in options
            and options.get('allow_zero', True)):
        return ''
    return _range_text(options.get('minimum'), options.get('maximum'),
                       options.get('allow_zero', True))
