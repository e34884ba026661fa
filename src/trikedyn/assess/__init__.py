"""The stability dossier for any trike (``trikedyn assess``): what it computes (:mod:`~trikedyn.assess.runs`,
:mod:`~trikedyn.assess.studies`, :mod:`~trikedyn.assess.dossier`), the guidelines derived from it
(:mod:`~trikedyn.assess.guidelines`), the requirements it is judged against (:mod:`~trikedyn.assess.requirements`)
and its HTML report (:mod:`~trikedyn.assess.report`). Nothing is imported here: each module is loaded when used.
"""
