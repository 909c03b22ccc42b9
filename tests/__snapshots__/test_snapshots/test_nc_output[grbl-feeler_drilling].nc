REFUSED (no NC program is written): feeler_drilling.apt:41: tapping: GRBL has no tapping cycle and no spindle synchronised with Z: a tap cannot be cut
