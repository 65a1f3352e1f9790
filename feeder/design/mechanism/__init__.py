"""Designing any mechanism: the sensitivities of its peak loads to the design variables of a
design file, and the variables that minimise a peak (``feeder design sensitivities|optimize
MODEL --closures F --design D --motion M``).

* :mod:`~feeder.design.mechanism.design_file` — the design file: variables, bounds, objective,
  constraints, the search's settings;
* :mod:`~feeder.design.mechanism.urdf_edit` — the URDF with the variables set;
* :mod:`~feeder.design.mechanism.evaluation` — a point run as ``feeder analyze`` runs it;
* :mod:`~feeder.design.mechanism.inputs` — the inputs checked before any folder is made;
* :mod:`~feeder.design.mechanism.sensitivities`, :mod:`~feeder.design.mechanism.outputs` — the
  sensitivities and their files;
* :mod:`~feeder.design.mechanism.problem` — the problem in SLSQP's epigraph form;
* :mod:`~feeder.design.mechanism.report`, :mod:`~feeder.design.mechanism.figure`,
  :mod:`~feeder.design.mechanism.optimize` — the optimisation's files;
* :mod:`~feeder.design.mechanism.meshes` — the model's mesh files copied beside the optimum.

The device's modules supply what the two share: the differences and their check, the epigraph
form, the search and its history, the tables and the heat map. Its public names are
re-exported by :mod:`feeder.design`, which loads them on first use.
"""
