"""3D rigid-block wall solver (Baraldi & Cecchi manuscript, DESIGN.md section 5).

Modules, one job each:

- ``interface``      interface strength domains and the n x n spring sub-model (manuscript 2.1)
- ``panel``          running-bond panel builder: blocks, interfaces, supports
- ``compatibility``  interface compatibility matrices H (manuscript Eq. 3, A1-A3)
- ``stiffness``      interface stiffness (Eq. 4-5), sparse panel stiffness H^T K H
- ``constitutive``   interface return mapping (Eq. 9, 10, 12-14) and damage states
- ``pushover``       incremental-iterative solver under displacement control
- ``settings``       the solver settings (``solver:`` of a case file)
- ``case``           YAML case files: reading, strict validation, problem-size limits, building
- ``dataset``        NetCDF output of one case
- ``figures``        damage maps and pushover curves
- ``validation``     manuscript Tables 1-3 and A1 beside the solver's numbers
- ``cli``            ``stonedem wall CASE.yaml -o OUT.nc``
"""
