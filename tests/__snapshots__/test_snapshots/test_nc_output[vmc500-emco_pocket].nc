REFUSED (no NC program is written): emco_pocket.gcode:47: deep_drill: the Acramatic cycle leaves the tool at R + GAGE_HT_MM (top + clearance): a higher retract plane cannot be written
