REFUSED (no NC program is written): emco_pocket.gcode:7: tool_change: hmCNC has no pause to change a tool in: post each tool's work as its own program
