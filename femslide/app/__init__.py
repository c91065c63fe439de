"""The application: structure and scene files, one run of any case, results, sweeps and the command line."""
