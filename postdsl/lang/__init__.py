"""The post language: a post's YAML read and checked into a typed model.

What a technologist writes - tables, items, formats, conditions, options, ``extends:`` -
and what a control does with its characters (:mod:`postdsl.lang.control_syntax`),
known before anything is compiled or run.
"""
