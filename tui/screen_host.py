"""What the main screen's mixins may use of the screen they are mixed into (types only).

:class:`~tui.main_screen.MainScreen` is assembled from mixins kept apart for
readability (:mod:`tui.grid_actions`, :mod:`tui.sample_program`,
:mod:`tui.sample_plot`); each calls the screen's Textual API (``notify``,
``query_one``, ``app``, ``workers``) and a few of the main screen's own methods.
For the type checker each mixin derives from :class:`ScreenHost`, a ``Screen``
that declares those methods; at run time the mixins derive from ``object`` (this
module is imported only under ``TYPE_CHECKING``), so the screen's MRO is what it
always was.  MainScreen's definitions override these declarations, and mypy checks
that their signatures agree.
"""

from __future__ import annotations

from typing import Any

from textual.screen import Screen

from tui.model import BlockView, TableRef

_MAIN_SCREEN = "defined by tui.main_screen.MainScreen"


class ScreenHost(Screen[None]):
    """The main screen's own methods that its mixins call (defined in MainScreen)."""

    def change(self, label: str, change: Any) -> bool:
        raise NotImplementedError(_MAIN_SCREEN)
    def show_commands(self) -> None: ...
    def blocks(self) -> list[BlockView]:
        raise NotImplementedError(_MAIN_SCREEN)
    def current_block(self) -> BlockView | None:
        raise NotImplementedError(_MAIN_SCREEN)
    def current_item(self) -> int | None:
        raise NotImplementedError(_MAIN_SCREEN)
    def _block_range(self) -> range:
        raise NotImplementedError(_MAIN_SCREEN)
    def select_table(self, ref: TableRef, focus: bool = False) -> None: ...
    def go_to_cell(self, ref: TableRef, block: int, column: int) -> None: ...
    def action_edit_sample(self) -> None: ...
    # the other mixins' methods that one mixin calls
    def replot(self) -> None: ...
    def repost(self) -> None: ...
