"""What a solution or a sweep says beyond its numbers: ``interpolate`` (interpolants of a
sweep), ``cycle`` (whether a sweep is one closed period), ``events`` (exact extremes and
roots), ``singular`` (rank analysis of Φ_q), ``locks`` (lock positions; why a solve
failed), ``assembly`` (assembly modes at one time)."""
