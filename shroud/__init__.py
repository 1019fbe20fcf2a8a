"""The shrouded-blade verification workbench as a library (``from shroud import api``).

The project's packages, in layers that import one way::

    workbench           the application: command line, runner, campaigns, reports, gates, compare
       |
    comparisons         studies (Table 1, Fig. 8, ...): compute -> plot -> report
       |
    reduced_model  reference_fe + meshes      model builders (declare their models to the core)
       |
    shroud.api          the public library: one call per analysis
       |
    shroud.analysis     parameter-driven runs of any registered model (transient, sweep, HB)
       |
    shroud.params       the parameter schema, validated once
       |
    shroud.core         physics: system, contact law, Newmark, harmonic balance, results
       |
    shroud.base         errors, logging, cache, MPI helpers (no physics)

A module imports only from its own layer or the ones below it
(tests/test_layers.py holds the graph).
"""
