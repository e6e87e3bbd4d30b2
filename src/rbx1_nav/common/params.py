"""Checks for ROS parameter values: each returns a raw value in the type the node needs or
raises ValueError naming the parameter (quoting <= 200 chars). rosparam's YAML 1.1 reads ``1e6``
and ``'false'`` as strings, so numbers may be numeric strings and flags 'true' / 'false'; bools
are never numbers, nor numbers flags. Lists and names: params_lists. No rospy here."""
import difflib
import math
import numbers
from collections import namedtuple

from rbx1_nav.common.params_given import private_name
from rbx1_nav.transform_utils import strip_leading_slash

__all__ = ['number', 'integer', 'flag', 'frame', 'text', 'raw', 'POSITIVE', 'Param', 'param',
           'read_all', 'describe', 'unknown', 'bounds', 'clear_text', 'check_all', 'unit_text',
           'UNIT_NAMES', 'start_text', 'command_line', 'leftovers', 'typos', 'shown']


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
        parts.append('%s %g' % ('>' if minimum == 0 and not allow_zero else '>=', minimum))
    zero_in_range = ((minimum is None or minimum < 0) and (maximum is None or maximum > 0))
    if not allow_zero and zero_in_range:
        parts.append('!= 0')
    if maximum is not None:
        parts.append('<= %g' % maximum)
    return ' and '.join(parts)


def number(name, value, minimum=None, maximum=None, allow_zero=True):
    """``value`` as a finite float in ``[minimum, maximum]`` (None: unbounded)."""
    result = _as_float(name, value)
    if not math.isfinite(result):
        raise ValueError('%s must be a finite number, got %.200r' % (name, value))
    if ((minimum is not None and result < minimum) or (maximum is not None and result > maximum)
            or (not allow_zero and result == 0.0)):
        raise ValueError('%s must be %s, got %.200r' % (
            name, _range_text(minimum, maximum, allow_zero), value))
    return result


def integer(name, value, minimum=None, maximum=None):
    """``value`` as an int in ``[minimum, maximum]``; integral floats and '1e3' too."""
    if isinstance(value, int) and not isinstance(value, bool):
        result = value
    else:
        as_float = _as_float(name, value)
        if not (math.isfinite(as_float) and as_float.is_integer()):
            raise ValueError('%s must be an integer, got %.200r' % (name, value))
        result = int(as_float)
    if (minimum is not None and result < minimum) or (maximum is not None and result > maximum):
        raise ValueError('%s must be an integer %s, got %.200r' % (
            name, _range_text(minimum, maximum, True), value))
    return result


def flag(name, value):
    """``value`` as a bool: a bool, or 'true' / 'false' (any case). Anything
    else is a ValueError rather than a guess: ``bool('false')`` is True."""
    if isinstance(value, bool):
        return value
    if isinstance(value, str) and value.strip().lower() in ('true', 'false'):
        return value.strip().lower() == 'true'
    raise ValueError('%s must be true or false, got %.200r' % (name, value))


def raw(name, value, **options):
    """``value`` as given, for another module to check (``options`` for --help)."""
    return value


def text(name, value, allow_empty=False):
    """``value`` stripped of surrounding whitespace. Where empty is allowed,
    None is empty too (``_plot:=~`` sets YAML's empty value, None)."""
    if value is None and allow_empty:
        return ''
    if not isinstance(value, str):
        raise ValueError('%s must be a string, got %.200r' % (name, value))
    result = value.strip()
    if not result and not allow_empty:
        raise ValueError('%s must not be empty' % name)
    return result


def frame(name, value, allow_empty=False):
    """``value`` as a tf2 frame id without a leading '/' or inner whitespace;
    '' only if ``allow_empty`` (where empty means "automatic")."""
    result = strip_leading_slash(text(name, value, allow_empty=True))
    if any(c.isspace() for c in result):
        raise ValueError('%s must be a frame id without spaces, got %.200r' % (name, value))
    if not result and not allow_empty:
        raise ValueError('%s must name a frame, got %.200r' % (name, value))
    return result


# Options for a number that must be greater than zero: number(..., **POSITIVE).
POSITIVE = dict(minimum=0.0, allow_zero=False)


Param = namedtuple('Param', 'name default check options unit doc note')
Param.__doc__ = """A node's private parameter; ``note`` joins ``unit`` in an error
about its value (say where a twin node or the book takes another unit)."""

#: Units as an error message spells them out.
UNIT_NAMES = {'m': 'metres', 'm/s': 'metres per second', 'rad': 'radians',
              'rad/s': 'radians per second', 'deg': 'degrees', 's': 'seconds', 'Hz': 'hertz'}


def param(name, default, check, unit='', doc='', note='', **options):
    """A :class:`Param`; keyword arguments beyond ``note`` go to ``check``."""
    return Param(name, default, check, options, unit, doc, note)


def unit_text(spec, value):
    """' (in radians; its note; 180 deg is 3.14159 rad)' for an error about
    ``spec``'s ``value`` (a bad radian value is likely degrees); '' unitless."""
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
    """(values, problems) of ``specs``, by ``lookup(name, default)``; bad ones keep the default."""
    values, problems = {}, []
    for spec in specs:
        value = lookup(spec.name, spec.default)
        try:
            values[spec.name] = spec.check(prefix + spec.name, value, **spec.options)
        except ValueError as err:
            problems.append(str(err) + unit_text(spec, value))
            values[spec.name] = spec.default
    return values, problems


def clear_text(node_name, names):
    """The ``rosparam delete`` of each of ``names`` of the node ``node_name``
    (values on the parameter server that its command line did not give)."""
    deletes = '; '.join('rosparam delete %s/%s' % (node_name.rstrip('/'), name) for name in names)
    return ('On the parameter server, not from this command line (an earlier run, a launch file '
            'or rosparam set): clear it with %s' % deletes)


def check_all(specs, lookup, node_name, given=frozenset()):
    """The checked values, or ValueError naming each bad one, and the
    ``rosparam delete`` of each not in ``given`` (this command line's,
    which a refused node leaves off the master: common.params_given)."""
    values, problems = read_all(specs, lookup, '~')
    if problems:
        bad = [spec.name for spec in specs
               if spec.name not in given and read_all([spec], lookup)[1]]
        raise ValueError('. '.join(['; '.join(problems)] + ([clear_text(node_name, bad)]
                                                            if bad else [])))
    return values


def shown(value, spec):
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
    return ', '.join(('%s %s %s' % (s.name, shown(values[s.name], s), s.unit)).strip()
                     for s in specs)


def start_text(specs, values):
    """A node's start-up line: :func:`describe` of the non-default values."""
    changed = [spec for spec in specs if values[spec.name] != spec.default]
    if not changed:
        return 'every parameter at its default (--help lists them)'
    return '%s; every other parameter at its default (--help lists them)' % (
        describe(changed, values))


def unknown(given, specs):
    """[(name, nearest known name or None)] for the names in ``given`` no spec declares."""
    known = [spec.name for spec in specs]
    return [(name, (difflib.get_close_matches(name, known, n=1) or [None])[0])
            for name in sorted(given) if name not in known]


def command_line(argv):
    """(``_name:=value`` names in ``argv``, as rospy reads them, whether
    roslaunch (``__log:=``) started the node)."""
    launched = any(arg.partition(':=')[0] == '__log' for arg in argv[1:])
    return {private_name(arg) for arg in argv[1:]} - {None}, launched


def typos(found, argv):
    """The line that stops a node for ``found`` unknown parameters, or None:
    one on the command line, or any under roslaunch (clear_params), is a typo
    that would run on the default; others are leftovers, only warned of."""
    given, launched = command_line(argv)
    bad = [(name, nearest) for name, nearest in found if launched or name in given]
    if not bad:
        return None
    listed = ', '.join('~%s%s' % (name, ' (did you mean ~%s?)' % nearest if nearest else '')
                       for name, nearest in bad)
    where = 'in the launch file' if launched else 'on the command line'
    return ('unknown parameter%s %s %s; not starting, so a misspelt name does not run on its '
            'default. Fix the name (--help lists them)' % ('s' * (len(bad) > 1), listed, where))


def leftovers(specs, values, argv, node_name):
    """A line naming the non-default values a rosrun-started node did not get
    from its command line (an earlier run's, or rosparam set), or None;
    ``node_name`` (``/calibrate_linear``) is the namespace to delete."""
    given, launched = command_line(argv)
    if launched:
        return None
    old = [spec for spec in specs if spec.name not in given and values[spec.name] != spec.default]
    if not old:
        return None
    return ('from the parameter server, not this command line (an earlier '
            'run on this master, or rosparam set): %s; `rosparam delete %s` '
            'to start clean' % (describe(old, values), node_name))


def bounds(spec):
    """A spec's bounds as its error message gives them ('> 0 and <= 2'), or ''."""
    options = spec.options
    return _range_text(options.get('minimum'), options.get('maximum'),
                       options.get('allow_zero', True))
