REFUSED (no NC program is written): work_offsets_router.jsonl:9: work_offset: hmCNC has no work offsets (thesis 7.1): only work offset 1, the zero set on the machine
