"""Tests of gearcalc.zstk (tests/zstk/test_<module>.py mirrors gearcalc/zstk/<module>.py)."""
