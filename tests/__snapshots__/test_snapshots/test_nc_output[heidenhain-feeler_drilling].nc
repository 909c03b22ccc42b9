REFUSED (no NC program is written): feeler_drilling.apt:44: rigid_tapping: cycles 207 and 209 (rigid tapping) have no dwell at the bottom
