"""FMU archives: locating the FMI 3.0 headers and schemas, writing, reading and checking .fmu files."""
