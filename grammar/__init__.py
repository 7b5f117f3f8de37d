"""The Lark grammars of RoboChart and RoboSim, shipped as package data (robogen.grammar)."""
