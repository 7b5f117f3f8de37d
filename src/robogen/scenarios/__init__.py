"""Scenarios for one model: build it (cached), drive it with timed events, check expectations.

The commands ``robogen simulate MODEL --scenario S.toml`` (:mod:`.simulate_cli`), ``robogen
scenario --template`` (:mod:`.template`) and ``robogen test`` (:mod:`.runner`). The scenario file
format and its player in the master are :mod:`robogen.cosim.scenario` and
:mod:`robogen.cosim.player`; docs/scenarios.md describes both.
"""
