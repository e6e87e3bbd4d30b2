"""A node's parameters as --help prints them (:func:`usage`) and as
docs/parameters.md shows them (:func:`markdown`, by `make docs`), from the
same declarations (rbx1_nav.common.params.Param), so the two cannot drift.
Loaded only for those: a node at work does not need it. No rospy here.
"""
import re

from rbx1_nav.common.params import shown, bounds

__all__ = ['usage', 'markdown']


def usage(doc, specs):
    """``--help`` text: the node's docstring and a table of ``specs``, one
    line each: name, default, what it does and its bounds.

    The table is the one list of a node's parameters; the docstring says
    what the node does, its topics and exit status.
    """
    lines = [(doc or '').strip(), '',
             'Private parameters (rosrun: _name:=value; launch: <param>):']
    width = max([len(spec.name) for spec in specs] + [4])
    for spec in specs:
        default = ('%s %s' % (shown(spec.default, spec), spec.unit)).strip()
        limits = bounds(spec)
        lines.append(('  ~%-*s  %-18s %s' % (width, spec.name, default, spec.doc
                                             + (' [%s]' % limits if limits else ''))
                      ).rstrip())
    return '\n'.join(lines)


def _summary(doc):
    """The first paragraph of a node's docstring, one line, without the
    'name.py - ' or 'name: ' it may start with."""
    first = ' '.join((doc or '').strip().split('\n\n', 1)[0].split())
    first = re.sub(r'^[a-z_]+(\.py)?( -|:) ', '', first)
    return first[:1].upper() + first[1:]


def _cell(text):
    """``text`` safe in a Markdown table cell."""
    return text.replace('|', '\\|')


def markdown(title, doc, specs):
    """A node's section of docs/parameters.md, from what --help prints
    (:func:`usage`): a heading ``title``, the summary from ``doc`` (the
    node's docstring), the rest of ``doc`` as text, and a table of
    ``specs``: parameter, default, unit, what it does, bounds."""
    rest = (doc or '').strip().split('\n\n', 1)[1:]
    lines = ['## `%s`' % title, '', _summary(doc), '']
    if rest:
        lines += ['```text', rest[0].strip('\n'), '```', '']
    lines += ['| parameter | default | unit | what it does | bounds |',
              '|---|---|---|---|---|']
    for spec in specs:
        limits = bounds(spec)
        lines.append('| `~%s` | `%s` | %s | %s | %s |' % (
            spec.name, _cell(shown(spec.default, spec)), _cell(spec.unit),
            _cell(spec.doc), _cell(limits)))
    return '\n'.join(lines) + '\n'
