"""Models of CNC controls: NC text in, typed motion events out (``events``).

A post names its control (``machine.control``); ``postdsl verify`` replays the
posted program through that model and compares the events with the CL.  Each
model states in its docstring which manual rules it follows.
"""

from __future__ import annotations

from postdsl.check.controls.acramatic import AcramaticControl
from postdsl.check.controls.base import ControlError, NCInput
from postdsl.check.controls.fanuc import FanucControl
from postdsl.check.controls.grbl import GrblControl
from postdsl.check.controls.heidenhain import HeidenhainControl
from postdsl.check.controls.hmcnc import HmcncControl
from postdsl.check.controls.iso import IsoControl
from postdsl.check.controls.linuxcnc import LinuxCNCControl
from postdsl.check.controls.sinumerik import SinumerikControl

#: model name (as a post's ``machine.control`` names it) -> model class
CONTROLS: dict[str, type[IsoControl]] = {
    cls.name: cls for cls in (FanucControl, LinuxCNCControl, SinumerikControl, AcramaticControl,
                              GrblControl, HmcncControl, HeidenhainControl)
}

__all__ = ["CONTROLS", "ControlError", "NCInput", "control_model"]


def control_model(name: str, *, calculator_input: bool = False) -> IsoControl:
    """A fresh model of the named control (one per program: models hold the modal state).

    ``calculator_input`` is the machine's setting (``machine: calculator_input``): a
    number without a decimal point is in mm, not in the least input increment.
    """
    model = CONTROLS[name]()
    model.configure(calculator_input=calculator_input)
    return model
