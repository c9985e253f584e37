"""gearcalc: engineering calculator for gear and mechanism designers."""

__version__ = "0.1.0"
