REFUSED (no NC program is written): work_offsets.jsonl:22: work_offset: GRBL 1.1 has the work offsets G54-G59 (1-6) only
