"""Tests of gearcalc.pins (tests/pins/test_<module>.py mirrors gearcalc/pins/<module>.py)."""
