"""Tests of gearcalc.report (tests/report/test_<module>.py mirrors gearcalc/report/<module>.py)."""
