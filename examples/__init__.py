"""Examples built with robogen. They live in the repository, beside the models they use, and are
not part of the installed package; run them from the repository root (``python -m
examples.ur5e.demo``)."""
