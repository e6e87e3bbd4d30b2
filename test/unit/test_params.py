"""Unit tests for rbx1_nav.common.params, the parameter checks every node uses."""
import math

import pytest
from hypothesis import given, strategies as st

from rbx1_nav.common.params import (POSITIVE, bounds, check_all, command_line, flag, frame,
                                    integer, leftovers, number, param, raw, start_text, text)
from rbx1_nav.common.params_help import markdown, usage
from rbx1_nav.common.params_lists import names, number_list, pairs, texts

finite = st.floats(allow_nan=False, allow_infinity=False)


# --- number ------------------------------------------------------------------

@given(finite)
def test_number_accepts_floats_and_their_strings(value):
    assert number('~x', value) == value
    assert number('~x', repr(value)) == value
    assert number('~x', ' %r ' % value) == value


@pytest.mark.parametrize('raw,expected', [(3, 3.0), ('1e6', 1e6), ('-2', -2.0),
                                          (0, 0.0), ('.5', 0.5)])
def test_number_converts(raw, expected):
    result = number('~x', raw)
    assert result == expected and type(result) is float


@pytest.mark.parametrize('bad', [True, False, None, 'fast', '', [1.0], {'a': 1},
                                 10 ** 400])
def test_number_rejects_non_numbers_naming_the_parameter(bad):
    with pytest.raises(ValueError, match=r'~rate must be a number'):
        number('~rate', bad)


@pytest.mark.parametrize('bad', [math.nan, math.inf, -math.inf, '.nan', 'inf',
                                 '-Infinity', 'nan'])
def test_number_rejects_nan_and_infinity(bad):
    with pytest.raises(ValueError, match=r'~freq must be a (finite )?number'):
        number('~freq', bad)


def test_number_bounds_are_inclusive_and_zero_can_be_excluded():
    assert number('~r', 0.0, minimum=0.0) == 0.0
    assert number('~r', 1000, minimum=0.0, maximum=1000.0) == 1000.0
    assert number('~r', 5e-324, minimum=0.0, allow_zero=False) == 5e-324
    with pytest.raises(ValueError, match=r'~r must be > 0 and <= 1000, got 0'):
        number('~r', 0, minimum=0.0, maximum=1000.0, allow_zero=False)
    with pytest.raises(ValueError, match=r'~r must be > 0 and <= 1000, got 1e\+308'):
        number('~r', 1e308, minimum=0.0, maximum=1000.0, allow_zero=False)
    with pytest.raises(ValueError, match=r'~r must be >= 1, got 0.5'):
        number('~r', 0.5, minimum=1.0)
    with pytest.raises(ValueError, match=r'~r must be != 0'):
        number('~r', '0', allow_zero=False)
    with pytest.raises(ValueError, match=r"got '-1'"):
        number('~r', '-1', minimum=0.0)


@given(finite, finite, finite)
def test_number_result_always_within_bounds(value, a, b):
    low, high = min(a, b), max(a, b)
    try:
        result = number('~x', value, minimum=low, maximum=high)
    except ValueError as err:
        assert '~x' in str(err)
        assert not low <= value <= high
    else:
        assert low <= result <= high and result == value


# --- integer -----------------------------------------------------------------

@pytest.mark.parametrize('raw,expected', [(3, 3), (3.0, 3), ('4', 4), ('1e3', 1000),
                                          (-2, -2)])
def test_integer_converts(raw, expected):
    result = integer('~legs', raw)
    assert result == expected and type(result) is int


@pytest.mark.parametrize('bad', [1.5, '2.5', True, math.nan, math.inf, None, 'x'])
def test_integer_rejects_non_integers(bad):
    with pytest.raises(ValueError, match='~legs must be'):
        integer('~legs', bad)


def test_integer_bounds():
    assert integer('~seed', 0, minimum=0) == 0
    with pytest.raises(ValueError, match=r'~seed must be an integer >= 0, got -1'):
        integer('~seed', -1, minimum=0)
    with pytest.raises(ValueError, match=r'<= 10'):
        integer('~legs', 11, minimum=1, maximum=10)


# --- flag --------------------------------------------------------------------

@pytest.mark.parametrize('raw,expected', [(True, True), (False, False),
                                          ('false', False), ('False', False),
                                          ('TRUE', True), (' true ', True)])
def test_flag_accepts_bools_and_their_strings(raw, expected):
    assert flag('~publish_tf', raw) is expected


@pytest.mark.parametrize('bad', ['yes', 'no', '', 0, 1, 1.0, None, 'flase', [True]])
def test_flag_rejects_everything_else(bad):
    with pytest.raises(ValueError, match='~publish_tf must be true or false'):
        flag('~publish_tf', bad)


# --- frame and text ----------------------------------------------------------

@pytest.mark.parametrize('raw,expected', [('odom', 'odom'), ('/odom', 'odom'),
                                          ('//robot1/base_link', 'robot1/base_link'),
                                          ('  /map ', 'map')])
def test_frame_strips_whitespace_and_leading_slashes(raw, expected):
    assert frame('~odom_frame', raw) == expected


@pytest.mark.parametrize('bad', ['', '  ', '/', '/ odom', 'base link', 5, None,
                                 ['odom'], True])
def test_frame_rejects_non_strings_and_empty(bad):
    with pytest.raises(ValueError, match='~odom_frame must'):
        frame('~odom_frame', bad)


def test_frame_may_be_empty_where_that_means_automatic():
    assert frame('~base_frame', '', allow_empty=True) == ''
    assert frame('~base_frame', ' / ', allow_empty=True) == ''
    with pytest.raises(ValueError, match='~base_frame must be a string'):
        frame('~base_frame', 3, allow_empty=True)


@given(st.text())
def test_frame_never_returns_a_leading_slash_or_padding(raw):
    try:
        result = frame('~f', raw, allow_empty=True)
    except ValueError:
        return
    assert not result.startswith('/')
    assert not any(c.isspace() for c in result)
    assert result == raw.strip().lstrip('/')


def test_text():
    assert text('~left_wheel_joint', ' wheel_l ') == 'wheel_l'
    for bad in ('', 7, None):
        with pytest.raises(ValueError, match='~left_wheel_joint must'):
            text('~left_wheel_joint', bad)
    # `rosrun ... _plot:=~` sets None (rospy ignores `_plot:=`): empty,
    # where empty is allowed (a frame too: _imu_frame:=~ is the automatic frame).
    assert text('~plot', None, allow_empty=True) == ''
    assert frame('~imu_frame', None, allow_empty=True) == ''
    with pytest.raises(ValueError, match='~plot must be a string'):
        text('~plot', 7, allow_empty=True)


# --- number_list -------------------------------------------------------------

def test_number_list_converts_each_item():
    assert number_list('~d', [1, '1e6', 0.5], 3, minimum=0.0) == [1.0, 1e6, 0.5]
    assert number_list('~d', (1, 2), 2) == [1.0, 2.0]


@pytest.mark.parametrize('bad,message', [
    ({'x': 1}, r'~d must be a list of 3 numbers'),
    ('1 2 3', r'~d must be a list of 3 numbers'),
    ([1, 2], r'~d must be a list of 3 numbers'),
    (None, r'~d must be a list of 3 numbers'),
    ([1, math.nan, 1], r'~d\[1\] must be a finite number'),
    ([1, 1, 0], r'~d\[2\] must be > 0'),
    ([1, 'x', 1], r'~d\[1\] must be a number'),
])
def test_number_list_rejects_with_the_parameter_and_index(bad, message):
    with pytest.raises(ValueError, match=message):
        number_list('~d', bad, 3, minimum=0.0, allow_zero=False)


# --- pairs (umbmark.py's ~measurements and ~odometry) -------------------------

def test_pairs_converts_each_pair_and_empty_is_none():
    assert pairs('~m', [[0.01, '-2e-3'], (0, 1)]) == [(0.01, -0.002), (0.0, 1.0)]
    assert pairs('~m', '') == [] and pairs('~m', []) == []


@pytest.mark.parametrize('bad,message', [
    ('0.1 0.2', r'~m must be a list of \[x, y\] pairs of numbers'),
    ([[0.1, 0.2, 0.3]], r'~m must be a list of \[x, y\] pairs of numbers'),
    ([0.1, 0.2], r'~m must be a list of \[x, y\] pairs of numbers'),
    ([[0.01, math.nan], [0, 0]], r'~m\[0\] must be a finite number'),
    ([[0, 0], ['x', 0]], r'~m\[1\] must be a number'),
])
def test_pairs_rejects_with_the_parameter_and_index(bad, message):
    with pytest.raises(ValueError, match=message):
        pairs('~m', bad)


def test_texts_takes_a_list_or_names_separated_by_spaces_and_empty_is_none():
    """lockstep_play.py's ~topics."""
    assert texts('~topics', [' /odom ', 'imu_data']) == ['/odom', 'imu_data']
    assert texts('~topics', ' /odom  imu_data ') == ['/odom', 'imu_data']
    assert texts('~topics', '') == [] and texts('~topics', None) == []
    assert texts('~topics', []) == []
    for bad, message in (([3], '~topics must be a string'), (['odom', ' '], 'must not be empty'),
                         (3, '~topics must be a string')):
        with pytest.raises(ValueError, match=message):
            texts('~topics', bad)


def test_range_message_mentions_zero_only_when_it_is_in_range():
    with pytest.raises(ValueError) as err:
        number('~w', 0.0, minimum=1e-3, maximum=10.0, allow_zero=False)
    assert str(err.value) == '~w must be >= 0.001 and <= 10, got 0.0'
    with pytest.raises(ValueError) as err:
        number('~b', 0, minimum=-1.0, maximum=1.0, allow_zero=False)
    assert str(err.value) == '~b must be >= -1 and != 0 and <= 1, got 0'


# --- names -------------------------------------------------------------------

def test_names_accepts_relative_ros_names_and_drops_a_leading_slash():
    assert names('~robots', ['robot1', '/robot2', ' fleet/r_3 ']) == [
        'robot1', 'robot2', 'fleet/r_3']
    assert names('~robots', ('a',)) == ['a']


@pytest.mark.parametrize('bad, message', [
    ([], 'non-empty list'), ('robot1', 'non-empty list'), (None, 'non-empty list'),
    (['robot 1'], r'~robots\[0\] must be a ROS name'),
    (['ok', '1robot'], r'~robots\[1\] must be a ROS name'),
    (['a//b'], 'must be a ROS name'), ([''], 'must be a ROS name'),
    (['a/'], 'must be a ROS name'), ([3], 'must be a ROS name'),
    (['r1', 'r2', '/r1'], "names 'r1' twice")])
def test_names_rejects_with_the_parameter(bad, message):
    with pytest.raises(ValueError, match=message):
        names('~robots', bad)


def test_names_maximum():
    assert len(names('~robots', ['r%d' % k for k in range(3)], maximum=3)) == 3
    with pytest.raises(ValueError, match='at most 3 names, got 4'):
        names('~robots', ['r%d' % k for k in range(4)], maximum=3)


@pytest.mark.parametrize('check', [number, integer, flag, text, frame])
def test_an_error_quotes_at_most_200_characters_of_the_value(check):
    huge = list(range(10 ** 6))
    with pytest.raises(ValueError) as err:
        check('~x', huge)
    assert len(str(err.value)) < 300


LEFTOVER_SPECS = (param('precise', False, flag), param('tf_wait', 5.0, number, 's'),
                  param('frame', 'odom', frame))


def test_command_line_names_the_private_parameters_and_sees_roslaunch():
    assert command_line(['node.py', '_precise:=true', '__name:=x', 'cmd_vel:=a',
                         '_tf_wait:=3']) == ({'precise', 'tf_wait'}, False)
    assert command_line(['node.py', '__name:=x', '__log:=/tmp/x.log']) == (set(), True)
    # As rospy reads them: a space ends the name.
    assert command_line(['node.py', '_a :=1', '_b/c:=2', ' _d:=1']) == ({'b/c'}, False)


def test_leftovers_name_non_default_values_not_on_the_command_line():
    values = {'precise': True, 'tf_wait': 25.0, 'frame': 'odom'}
    line = leftovers(LEFTOVER_SPECS, values, ['node.py'], '/odom_out_and_back')
    assert line == ('from the parameter server, not this command line (an '
                    'earlier run on this master, or rosparam set): precise on, '
                    'tf_wait 25 s; `rosparam delete /odom_out_and_back` to '
                    'start clean')
    line = leftovers(LEFTOVER_SPECS, values, ['node.py', '_precise:=true'], '/n')
    assert 'precise' not in line and 'tf_wait 25 s' in line


def test_no_leftovers_at_defaults_from_the_command_line_or_under_roslaunch():
    values = {'precise': True, 'tf_wait': 5.0, 'frame': 'odom'}
    assert leftovers(LEFTOVER_SPECS, values, ['node.py', '_precise:=true'], '/n') is None
    assert leftovers(LEFTOVER_SPECS, dict(values, precise=False), ['node.py'], '/n') is None
    # Every launch file clears the node's parameters: they are its own.
    assert leftovers(LEFTOVER_SPECS, values, ['node.py', '__log:=/tmp/n.log'], '/n') is None


CLEAR_SPECS = (param('linear_speed', 0.2, number, 'm/s', 'forward speed',
                     maximum=2.0, **POSITIVE),
               param('goal_angle', 90.0, number, 'deg', 'turn', minimum=-720.0,
                     maximum=720.0),
               param('precise', False, flag, '', 'slow down near each goal'))


def test_a_bad_value_error_names_the_rosparam_delete_of_each_bad_parameter():
    given = {'linear_speed': -1, 'goal_angle': 'x', 'precise': True}
    with pytest.raises(ValueError) as err:
        check_all(CLEAR_SPECS, lambda name, default: given.get(name, default),
                  '/robot1/nav_square')
    message = str(err.value)
    assert message.startswith('~linear_speed must be > 0 and <= 2, got -1 (in '
                              'metres per second); ~goal_angle must be a '
                              "number, got 'x' (in degrees). ")
    assert message.endswith('(in degrees). On the parameter server, not from this command '
                            'line (an earlier run, a launch file or rosparam set): clear '
                            'it with rosparam delete /robot1/nav_square/linear_speed; '
                            'rosparam delete /robot1/nav_square/goal_angle')
    assert 'NAME' not in message and '/precise' not in message


def test_a_bad_value_from_the_command_line_has_no_rosparam_delete():
    # A refused node leaves its command line's values off the master
    # (rbx1_nav.common.params_given): nothing there to delete.
    given = {'linear_speed': -1, 'goal_angle': 'x'}
    with pytest.raises(ValueError) as err:
        check_all(CLEAR_SPECS, lambda name, default: given.get(name, default), '/n',
                  given={'linear_speed'})
    assert str(err.value).endswith('clear it with rosparam delete /n/goal_angle')
    with pytest.raises(ValueError) as err:
        check_all(CLEAR_SPECS, lambda name, default: given.get(name, default), '/n',
                  given={'linear_speed', 'goal_angle'})
    assert str(err.value).endswith("got 'x' (in degrees)") and 'rosparam' not in str(err.value)


def test_check_all_returns_the_checked_values():
    given = {'linear_speed': '0.5', 'precise': 'true'}
    assert check_all(CLEAR_SPECS, lambda name, default: given.get(name, default),
                     '/n') == {'linear_speed': 0.5, 'goal_angle': 90.0,
                               'precise': True}


def test_help_lists_each_parameter_once_with_default_and_bounds():
    text = usage('node.py - a node.', CLEAR_SPECS)
    assert text.count('~linear_speed ') == 1
    assert bounds(CLEAR_SPECS[0]) == '> 0 and <= 2'
    assert bounds(CLEAR_SPECS[2]) == ''
    lines = text.split('Private parameters (rosrun: _name:=value; launch: '
                       '<param>):\n', 1)[1].splitlines()
    assert lines[0].split() == ['~linear_speed', '0.2', 'm/s', 'forward',
                                'speed', '[>', '0', 'and', '<=', '2]']
    assert lines[2].split() == ['~precise', 'off', 'slow', 'down', 'near',
                                'each', 'goal']



# -- markdown: the docs page's section of a node, from what --help prints ----

DOC = """node.py - drive a node
somewhere.

Publishes:  cmd_vel
Exit status: 0 after a completed course.
"""


def test_markdown_gives_the_summary_the_rest_and_a_row_per_parameter():
    text = markdown('node.py', DOC, CLEAR_SPECS)
    lines = text.splitlines()
    assert lines[:4] == ['## `node.py`', '', 'Drive a node somewhere.', '']
    assert lines[4:8] == ['```text', 'Publishes:  cmd_vel',
                          'Exit status: 0 after a completed course.', '```']
    rows = [line for line in lines if line.startswith('| `~')]
    assert [row.split('|')[1].strip() for row in rows] == [
        '`~%s`' % spec.name for spec in CLEAR_SPECS]
    assert rows[0] == '| `~linear_speed` | `0.2` | m/s | forward speed | > 0 and <= 2 |'
    assert rows[2] == '| `~precise` | `off` |  | slow down near each goal |  |'
    assert text.endswith('|\n')


def test_markdown_escapes_table_bars_and_keeps_bounds_of_a_raw_parameter():
    specs = [param('mode', 'a|b', text, '', 'a | b'),
             param('mass', 6.0, raw, 'kg', 'checked elsewhere', minimum=0.0,
                   maximum=1000.0, allow_zero=False)]
    rows = [line for line in markdown('n', 'n: one line.', specs).splitlines()
            if line.startswith('| `~')]
    assert rows[0] == '| `~mode` | `a\\|b` |  | a \\| b |  |'
    assert rows[1] == '| `~mass` | `6` | kg | checked elsewhere | > 0 and <= 1000 |'
    assert raw('~mass', 'x', minimum=0.0) == 'x'
    assert '```' not in markdown('n', 'n: one line.', specs)

# -- typos: an unknown parameter given to the node stops it ----------------

from rbx1_nav.common import params  # noqa: E402

def test_a_typo_on_the_command_line_stops_the_node():
    specs = [params.param('goal_distance', 1.0, params.number, 'm', 'how far')]
    found = params.unknown({'goal_distnace': 0.5}, specs)
    assert found == [('goal_distnace', 'goal_distance')]
    text = params.typos(found, ['odom_out_and_back.py', '_goal_distnace:=0.5'])
    assert text.startswith('unknown parameter ~goal_distnace (did you mean '
                           '~goal_distance?) on the command line; not starting')
    assert '\n' not in text


def test_a_typo_in_a_launch_file_stops_the_node():
    found = [('goal_distnace', 'goal_distance'), ('zzz', None)]
    text = params.typos(found, ['odom_out_and_back.py', '__name:=x',
                                '__log:=/tmp/x.log'])
    assert text.startswith('unknown parameters ~goal_distnace (did you mean '
                           '~goal_distance?), ~zzz in the launch file;')


def test_a_leftover_on_the_master_only_warns():
    found = [('goal_distnace', 'goal_distance')]
    assert params.typos(found, ['odom_out_and_back.py']) is None
    assert params.typos(found, ['odom_out_and_back.py', '_rate:=10']) is None
    assert params.typos([], ['odom_out_and_back.py', '__log:=/tmp/x.log']) is None


def test_a_range_or_type_error_names_the_unit_and_where_the_books_nodes_differ():
    """_goal_angle:=180 on odom_out_and_back.py: radians, as the book's
    script, converted; nav_square.py's goal_angle is in degrees."""
    from rbx1_nav.motion.course.book import NAV_SQUARE, OUT_AND_BACK

    def error(specs, name, value):
        return check_errors(specs, {name: value})

    def check_errors(specs, given):
        with pytest.raises(ValueError) as err:
            check_all(specs, lambda name, default: given.get(name, default),
                      '/course')
        return str(err.value)

    text = error(OUT_AND_BACK.params, 'goal_angle', 180)
    assert ('~goal_angle must be >= -12.5664 and <= 12.5664, got 180 (in '
            "radians; as in the book's odom_out_and_back.py and "
            "timed_out_and_back.py; nav_square.py takes degrees; 180 deg is "
            '3.14159 rad)') in text
    text = error(NAV_SQUARE.params, 'goal_angle', 'ninety')
    assert ("~goal_angle must be a number, got 'ninety' (in degrees; as in the "
            "book's nav_square.py; odom_out_and_back.py and "
            'timed_out_and_back.py take radians)') in text
    assert '(in metres per second)' in error(OUT_AND_BACK.params, 'linear_speed', -1)
    # A parameter without a unit gets nothing added.
    assert error(OUT_AND_BACK.params, 'legs', 0).startswith(
        '~legs must be an integer >= 1 and <= 1000, got 0. ')


def test_the_start_up_line_names_only_what_differs_from_the_defaults():
    values = {'precise': False, 'tf_wait': 5.0, 'frame': 'odom'}
    assert start_text(LEFTOVER_SPECS, values) == (
        'every parameter at its default (--help lists them)')
    assert start_text(LEFTOVER_SPECS, dict(values, precise=True, tf_wait=2.5)) == (
        'precise on, tf_wait 2.5 s; every other parameter at its default '
        '(--help lists them)')
