"""navlab.surenav: SuReNav, learning which soft-constrained regions a person would cross when the sidewalk
is blocked (Sec. and Eq. numbers below are the paper's, ``track.py`` cites it; where this track sits among
the layers: ``docs/design.md``).

Method (one concept per module, each docstring naming its section and equation):

* ``model``: the relaxation-cost estimator Psi_G (Sec. IV-C.2, Eq. 8): graph inputs (Eq. 7), GatedGCN,
  the GraphGPS stack.
* ``training_data``, ``loss``, ``train``: samples from the demonstrations (Sec. IV-C.1), the false-relaxation
  loss Eq. 12 with the sample weights Eq. 13-14, and end-to-end training through the differentiable graph
  A*; ``blackbox`` is the blackbox-gradient variant row (Vlastelica et al.).
* ``semi_static``, ``policy``, ``windows``: interleaved relax-plan-execute (Algorithm 1, Sec. V) in a
  semi-static map, and the planning window.
* ``baselines``: D* Lite, COA*, rule-based relaxation (RCR), the per-label cost fields.

Benchmark: ``context`` (the context demonstrator the paper's claims are decided on, with its tiles and
estimators), ``experts`` (the per-label demonstrator: a control), ``episodes`` and ``benchmark`` (Table I and
Fig. 4's runs), ``demo_priors``, ``estimator_report``, ``tables``, ``paper`` (the printed numbers) and
``claims`` (the paper's sentences, decided strictly). Build steps: ``artifacts``, ``steps``; the manifest the
pipeline reads: ``track``.
"""
