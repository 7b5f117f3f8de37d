"""robogen: RoboChart/RoboSim models to FMI 3.0 co-simulation FMUs, and a clock-aware master."""

__version__ = "0.1.0"
