"""The parametric study: its grid of cases, threshold searches, cubes, jobs and reductions."""
