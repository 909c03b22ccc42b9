REFUSED (no NC program is written): feeler_milling.apt:60: arc_move: an arc outside the XY plane: with TOOL CALL Z the TNC's working plane is XY, and this post writes no circles in the ZX or YZ plane
