"""Unit tests for rbx1_nav.common.params_given: the command line's private
parameters as rospy reads them, and what a refused node puts back."""
import rosgraph.names
import rospy.client
import rospy.exceptions

from rbx1_nav.common.params_given import lookup, private_name, put_back

#: Arguments of every kind rospy's init_node meets: private parameters
#: (nested, YAML values, repeated, empty, malformed), remappings, special
#: keys, a space that makes an argument no remapping, a bare '_'.
ARGV = ['odom_out_and_back.py', '_goal_distnce:=0.5', '_legs:= [1, 2] ', '__name:=course',
        'cmd_vel:=mobile_base/commands/velocity', '_plot:=', '_precise:=true', '_a/b:=0.25',
        ' _c:=1', '_d :=1', '~e:=1', '_:=3', '_goal_distnce:=0.7', "_s:='false'", '_n:=1e6',
        '__log:=/tmp/x.log', 'positional', '_x\n:=1', '1_a:=b', '/a:=b']


def _rospy_sets_or_refuses(arg):
    try:
        return bool(rospy.client.load_command_line_node_params([arg]))
    except rospy.exceptions.ROSInitException:
        return True


def test_what_init_node_does_not_get_is_what_rospy_would_set_as_a_parameter():
    for arg in ARGV + ['_x:=a:=b', '_x:=[1,', 'a:=', '', '_a:=1\n2', '__x:=1']:
        taken = private_name(arg) is not None
        assert _rospy_sets_or_refuses(arg) <= taken, arg  # all of those
        assert taken <= rosgraph.names.is_legal_remap(arg), arg  # and only remappings


def test_init_node_without_the_private_parameters_sets_none():
    kept = [arg for arg in ARGV if private_name(arg) is None]
    assert kept == ['odom_out_and_back.py', '__name:=course',
                    'cmd_vel:=mobile_base/commands/velocity', ' _c:=1', '_d :=1', '~e:=1',
                    '_:=3', '__log:=/tmp/x.log', 'positional', '_x\n:=1', '1_a:=b', '/a:=b']
    # rospy would set none of what is left, and rosgraph keeps its remappings.
    assert rospy.client.load_command_line_node_params(kept) == {}
    assert rosgraph.names.load_mappings(kept) == rosgraph.names.load_mappings(ARGV)
    names = {private_name(arg) for arg in ARGV} - {None}
    assert names - {'plot'} == set(rospy.client.load_command_line_node_params(ARGV))
    # One rospy would refuse is kept from init_node too: the node says why.
    assert private_name('_x:=a:=b') == 'x'


def test_lookup_reads_a_name_in_a_namespace_as_the_master_gives_it():
    tree = {'legs': 2, 'a': {'b': 0.25, 'c': {}}}
    assert lookup(tree, 'a/b') == 0.25 and lookup(tree, 'a/d', 'no') == 'no'
    assert lookup(tree, 'legs/x', 'no') == 'no' and lookup({}, 'legs', 3) == 3
    assert lookup(tree, 'a/c') == {} and lookup(tree, '/legs/') == 2


def test_put_back_deletes_what_was_new_and_restores_what_was_replaced():
    # The user's `rosparam set ~legs 1` before a run given _legs:=2 and a typo.
    before = {'legs': 1, 'goal_distance': 0.5, 'a': {'b': False}}
    assert put_back(before, {'legs': 2, 'goal_distnce': 0.7, 'a/b': True, 'a/c': 1}) == (
        ['a/c', 'goal_distnce'], {'legs': 1, 'a/b': False})
    assert put_back({}, {}) == ([], {})


def test_the_command_line_goes_over_the_masters_namespace():
    from rbx1_nav.common.params_given import layered
    get = layered({'rate': 15, 'a/b': 2}, {'rate': 20, 'legs': 3, 'a': {'b': 1}})
    assert get('rate', None) == 15  # the command line's
    assert get('legs', None) == 3   # the master's
    assert get('a/b', None) == 2
    assert get('goal_distance', 1.0) == 1.0  # neither: the default
