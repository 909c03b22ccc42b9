REFUSED (no NC program is written): vmc500_cycles.jsonl:36: rigid_tapping: a rigid tap (G33.1 in LinuxCNC) is not written by this post: tap with a floating holder (the CL's tapping, G84/G74)
