REFUSED (no NC program is written): feeler_milling.apt:11: spindle_on: the hmCNC spindle turns at the speed set on it (option spindle_speed_rpm); the CL's speed cannot be written
