REFUSED (no NC program is written): boring_spindle_stop.jsonl:5: boring_spindle_stop: the VMC 500 post knows the thesis's drilling cycles only: boring with a spindle stop is not written
