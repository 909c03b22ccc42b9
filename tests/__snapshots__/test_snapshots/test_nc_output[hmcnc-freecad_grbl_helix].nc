REFUSED (no NC program is written): freecad_grbl_helix.nc:24: spindle_on: the hmCNC spindle turns at the speed set on it (option spindle_speed_rpm); the CL's speed cannot be written
