REFUSED (no NC program is written): feeler_drilling.apt:44: rigid_tapping: G84.1 has no dwell at the bottom
