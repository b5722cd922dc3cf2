"""Forces in the model language: mass properties and loads declared on a `Model` (`loads`),
their generalized forces in the model's coordinates (`dynamics`), and the rows that hold a
model moved by its forces alone at its guess (`holds`). Sympy only."""
