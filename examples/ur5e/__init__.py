"""The UR5e case study of the paper, end to end: build the FMUs, co-simulate the scenario in
its variants, analyse the runs, draw the figure and write the summary (`make demo`, which runs
``python -m examples.ur5e.demo``). It uses the models of ``models/ur5e/``."""
