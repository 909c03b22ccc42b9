REFUSED (no NC program is written): hmcnc_sign.jsonl:10: spindle speed 20000 rpm is outside the range of HEIDENHAIN TNC 640 generic VMC (0 to 12000 rpm)
