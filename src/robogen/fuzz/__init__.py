"""The model fuzzer of issue 23: random, well-formed RoboChart and RoboSim models, seeded and
reproducible, each checked for the properties of :mod:`robogen.fuzz.properties` (print and parse
give the same AST; check reports no error; package gives a valid FMU or a located "not
supported"; the FMU and the reference interpreter agree; on a sample, the C runs clean under
the sanitizers), failures shrunk to small regression files. ``python -m robogen.fuzz`` and
``make fuzz`` run it; docs/fuzzing.md explains it.

The top of robogen's layering: it uses every stage, and no module of robogen imports it.
"""
