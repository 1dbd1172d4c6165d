"""Base motion: excitation kinds (harmonic, pulses, records), record files, suites and their CLI."""
