"""Runs of a scenario: what a run costs and whether it may start, and the runs themselves.

The layer between the scenario (:mod:`pdamper.io`, which parses and builds) and the
reports (:mod:`pdamper.reports`, which render):

* :mod:`pdamper.runs.resources`: the memory and time each run of a scenario implies,
  judged against the limits of :mod:`pdamper.resources` before the run starts;
* :mod:`pdamper.runs.maps`: the effective-field maps of a scenario on the sweep engine;
* :mod:`pdamper.runs.realisations`: DEM answers from N random packings, and the summary of
  one Level II DEM run;
* :mod:`pdamper.runs.uncertainty`: the propagation of a scenario's uncertain inputs to its
  answers;
* :mod:`pdamper.runs.paper_case_study`, :mod:`pdamper.runs.damper_report`,
  :mod:`pdamper.runs.cor_sensitivity`: the runs of ``pdamper paper``, ``pdamper report``
  and ``pdamper cor-sensitivity``, whose pages and figures :mod:`pdamper.reports` makes.

Nothing is imported here: ``import pdamper.runs`` stays cheap.
"""
