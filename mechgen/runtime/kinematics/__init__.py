"""The kinematics of a Mechanism's state (runtime.state): a solve at one time, sweeps
over many, the path solve(t) follows from the guess, where solves start, sweeps across
stage switches. Each function takes the state (or the mechanism whose state it reads)
and returns results; none calls the Mechanism's methods."""
