"""CL data: the command vocabulary and the readers that produce it, side by side."""

from postdsl.cl.model import COMMANDS, PARAMETERS, CLCommand

__all__ = ["COMMANDS", "PARAMETERS", "CLCommand"]
