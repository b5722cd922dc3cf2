"""The sorted solver of a module: the structure of Φ (`blocks`: matching, Tarjan, tearing),
the solver plan decided once as frozen data (`plan`), RRR dyads and signed closed forms
(`dyads`), and the emitters of the block-by-block position solver (`position`), the linear
velocity and acceleration passes (`linear`) and the fast sweep (`sweep`). Built on
`compiler.codegen`."""
