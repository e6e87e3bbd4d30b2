"""The command line's private parameters (``_name:=value``), kept off the master until the node
starts: rospy's init_node sets them before the node has looked at them, so a refused start (a
typo, a bad value) left them for every later run (rbx1_nav.common.node_ros). No rospy here."""
import re

__all__ = ['private_name', 'lookup', 'layered', 'put_back']

#: rosgraph.names.REMAP_PATTERN, matched whole (test_params_given checks the two agree).
_REMAP = re.compile(r'([\~\/A-Za-z]|_|__)[\w\/]*:=.*')
_MISSING = object()


def private_name(arg):
    """The private parameter ``arg`` sets as rospy's init_node reads it ('a' or 'a/b'), or None."""
    source = arg.split(':=', 1)[0].strip() if _REMAP.fullmatch(arg) else ''
    return source[1:] if len(source) > 1 and source[0] == '_' and source[1] != '_' else None


def lookup(tree, name, default=None):
    """The value of ``name`` in the namespace ``tree`` (nested dicts, as the master gives it)."""
    for part in (part for part in name.split('/') if part):
        if not isinstance(tree, dict) or part not in tree:
            return default
        tree = tree[part]
    return tree


def layered(given, before):
    """``lookup(name, default)`` for a node's parameters: the command line's ``given`` ({name:
    value}, not on the master yet) over the master's namespace ``before``."""
    return lambda name, default: given[name] if name in given else lookup(before, name, default)


def put_back(before, names):
    """(names to delete, {name: old value}) that undo setting ``names`` on the namespace
    ``before`` as it was: a name that was there gets its value back, a new one goes."""
    old = {name: lookup(before, name, _MISSING) for name in names}
    return (sorted(name for name, value in old.items() if value is _MISSING),
            {name: value for name, value in old.items() if value is not _MISSING})
