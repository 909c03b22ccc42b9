"""A checked post made into code, once: its tables compiled, then written out as one
Python module (:mod:`postdsl.compile.codegen`) that is the only way a post runs, with
what that module needs at run time (:mod:`postdsl.compile.runtime`) and the caches
that keep both between runs."""
