"""The commands pane: every CL command by group, marked as the sample program and post see it.

``●`` the sample program uses the command; a dim ``·`` name: the post has no
table for it (``✗`` in red when the sample program needs it); ``→ other``: the
command is written with another command's table; a red ``!``: its table has
problems.  Custom cycles and structures (shared blocks) follow the groups.
"""

from __future__ import annotations

from dataclasses import dataclass

from rich.text import Text
from textual.message import Message
from textual.widgets import Tree
from textual.widgets.tree import TreeNode

from postdsl import api
from tui.model import TableRef, title_of


@dataclass(frozen=True)
class Entry:
    ref: TableRef
    has_table: bool
    redirect: str | None = None
    #: the table comes from the post this one extends (``extends:``)
    inherited: bool = False


def entries(post: api.Post) -> dict[str, list[Entry]]:
    """The pane's groups and their entries, from the post's model."""
    commands = post.commands
    groups: dict[str, list[Entry]] = {}
    for group, names in api.command_groups().items():
        rows = []
        for name in names:
            if name == "custom_cycle":
                continue
            node = commands.get(name)
            redirect = node.redirect if node is not None else None
            rows.append(Entry(TableRef("command", name), name in commands, redirect,
                              post.inherited(("commands", name))))
        if group == "probing":
            rows += [Entry(TableRef("cycle", str(name)), True, None,
                           post.inherited(("custom_cycles", name)))
                     for name in post.custom_cycles]
        if rows:
            groups[group] = rows
    for name in commands:
        if name not in {e.ref.name for rows in groups.values() for e in rows}:
            groups.setdefault("other", []).append(Entry(TableRef("command", str(name)), True))
    structures = [Entry(TableRef("structure", str(name)), True, None,
                        post.inherited(("structures", name)))
                  for name in post.structures]
    if structures:
        groups["structures"] = structures  # not a post: the pane's group
    return groups


class CommandsPane(Tree[TableRef]):
    """A tree of the post's tables; moving the cursor shows a table, enter goes to it."""

    class Chosen(Message):
        """A table was highlighted (``go`` when chosen with enter: focus the grid)."""

        def __init__(self, ref: TableRef, go: bool) -> None:
            super().__init__()
            self.ref = ref
            self.go = go

    def __init__(self, id: str | None = None) -> None:
        super().__init__("post", id=id)
        self.show_root = False
        self.guide_depth = 2
        self._shape: list[tuple[str, list[tuple[TableRef, bool]]]] = []
        self._ref_nodes: dict[TableRef, TreeNode[TableRef]] = {}
        self._pending: TableRef | None = None
        self._labels: dict[TableRef, Text] = {}

    def show(self, post: api.Post, used: set[str],
             troubled: set[TableRef], current: TableRef | None) -> None:
        """Fill or update the tree; rebuilt only when the set of tables changed."""
        groups = entries(post)
        shape = [(group, [(e.ref, e.has_table) for e in rows]) for group, rows in groups.items()]
        if shape != self._shape:
            self._shape = shape
            self.clear()
            self._ref_nodes = {}
            self._labels = {}
            for group, rows in groups.items():
                branch = self.root.add(Text(group, style="bold"), expand=True)
                branch.allow_expand = True
                for entry in rows:
                    self._ref_nodes[entry.ref] = branch.add_leaf("", data=entry.ref)
        for rows in groups.values():
            for entry in rows:
                node = self._ref_nodes.get(entry.ref)
                label = self._label(entry, used, troubled)
                if node is not None and self._labels.get(entry.ref) != label:
                    # only changed labels: each one costs the tree a redraw
                    self._labels[entry.ref] = label
                    node.set_label(label)
        if current is not None and current in self._ref_nodes:
            node = self._ref_nodes[current]
            if self.cursor_node is not node:
                # the node's line is known only once the tree has laid its lines out; until
                # the cursor is there, highlights come from the program, not the user
                self._pending = current
                self.call_after_refresh(self._go_to, current)

    def node_for(self, ref: TableRef) -> TreeNode[TableRef] | None:
        return self._ref_nodes.get(ref)

    def _go_to(self, ref: TableRef) -> None:
        node = self._ref_nodes.get(ref)
        if node is None or self.cursor_node is node:
            self._pending = None
        else:
            self.move_cursor(node)

    @staticmethod
    def _label(entry: Entry, used: set[str], troubled: set[TableRef]) -> Text:
        name = entry.ref.name
        is_used = name in used
        label = Text()
        if not entry.has_table:
            label.append("✗ " if is_used else "· ", style="bold red" if is_used else "dim")
            label.append(title_of(name), style="red" if is_used else "dim")
            return label
        label.append("● " if is_used else "  ", style="green")
        label.append(title_of(name))
        if entry.redirect:
            label.append(f" → {title_of(entry.redirect)}", style="dim italic")
        if entry.inherited:
            label.append(" ↑", style="cyan")  # from the base post (extends:)
        if entry.ref in troubled:
            label.append(" !", style="bold red")
        return label

    def on_tree_node_highlighted(self, event: Tree.NodeHighlighted[TableRef]) -> None:
        event.stop()
        if self._pending is not None:
            if event.node.data == self._pending:
                self._pending = None
            return
        if event.node.data is not None:
            self.post_message(self.Chosen(event.node.data, go=False))

    def on_tree_node_selected(self, event: Tree.NodeSelected[TableRef]) -> None:
        event.stop()
        if event.node.data is not None:
            self.post_message(self.Chosen(event.node.data, go=True))
