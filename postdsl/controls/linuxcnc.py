"""LinuxCNC control model: the ISO core with LinuxCNC's rules (its G-code reference).

- comments are ``( … )`` or ``;`` to the end of the line; ``%`` marks the program;
- ``G4 P`` and the P of G82/G86/G88/G89 are seconds;
- there is no M29: G84/G74 tap with the running spindle (``tap``, not ``rigid_tap``).

Its events are cross-checked against LinuxCNC's own interpreter ``rs274``
(tests/test_controls_rs274.py) on programs of the dialect the two share.
"""

from __future__ import annotations

from typing import ClassVar

from postdsl.controls.events import Origin
from postdsl.controls.iso import IsoControl


class LinuxCNCControl(IsoControl):
    name = "linuxcnc"
    cycles: ClassVar[dict[str, tuple[str, str]]] = {
        **IsoControl.cycles, "86": ("bore", "P"), "88": ("bore", "P")}

    def code_of(self, text: str, origin: Origin) -> str:
        code = super().code_of(text.split(";", 1)[0], origin)
        return "" if code.strip() == "%" else code
