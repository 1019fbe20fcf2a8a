"""The shrouded-blade verification workbench, in layers that import one way::

    shroud.app          command line, runner, campaigns, scenes, reports, gates
       |
    comparisons         studies (Table 1, Fig. 8, ...): compute -> plot -> report
       |
    reduced_model  reference_fe + meshes      model builders (register with the core)
       |
    shroud.analysis     parameter-driven runs of any registered model (transient, sweep)
       |
    shroud.params       the parameter schema, validated once
       |
    shroud.core         physics: system, contact law, Newmark, harmonic balance, results
       |
    shroud.base         errors, logging, cache, MPI helpers (no physics)

A module imports only from its own layer or the ones below it
(tests/test_layers.py holds the graph).
"""
