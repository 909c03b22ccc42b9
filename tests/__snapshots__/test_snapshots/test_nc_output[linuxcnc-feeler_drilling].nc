REFUSED (no NC program is written): feeler_drilling.apt:44: rigid_tapping: LinuxCNC's G33.1 reverses the spindle at the bottom without a dwell: a rigid tap with a dwell cannot be written
