"""The postdsl table editor (Textual): ``postdsl edit MACHINE [--cl SAMPLE]``.

Map of the package:

* ``app``            the application: the document, save/undo/quit, help, screens' keys
* ``main_screen``    the main screen: its state (table, cursor, sample) as reactive attributes
* ``grid_actions``, ``sample_program``  its actions on the grid, and its sample program
* ``messages``       DocumentChanged: how every screen learns of an edit
* ``document``       the post being edited: text, round-trip document, undo/redo, saving
* ``merge``          saves stay byte-identical outside what was edited
* ``edits``          in-place edits of the round-trip document (items, blocks, values)
* ``model``          what the widgets show, computed from the document (no Textual)
* ``commands_pane``, ``command_table``, ``preview_pane``, ``program_view``,
  ``trace_pane``, ``footer``                                   the main screen's widgets
* ``sample``, ``posting``  the sample program: read, posted (a long one in a child process)
* ``sample_picker``, ``help_screen``                            f6 and f1
* ``item_editor``, ``block_editor``, ``dialogs``                            dialogs
* ``formats_editor``, ``variables_editor``, ``settings_editor``, ``fields``  editor screens
* ``screens``        the registry of editor screens (other tools add theirs there)
* ``palette``        the command palette's provider
* ``editor.tcss``    all styling

Only ``postdsl.api`` and the loader's round-trip document are used from the library.
"""
