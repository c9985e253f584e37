"""Exploring a design space over the grid sweep's pure chunks: filters (``--where``), samplers (``--sample``),
``gearcalc optimize`` and ``gearcalc sensitivity``.  One process, ``--jobs`` and a Dask cluster evaluate the same
chunks, so they give the same answer.  Nothing here is imported by ``gearcalc --help`` or a single design;
scipy is imported only by the samplers, the optimiser and the sensitivity analysis."""
