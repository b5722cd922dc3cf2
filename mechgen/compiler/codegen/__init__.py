"""How the compiler writes code: a small statement IR (`ir`), sympy expressions printed as
numba-friendly Python (`printer`), the identifier each model symbol gets (`names`), common
subexpressions scheduled before their first use (`schedule`) and the locals a function
reads from its argument arrays (`inputs`). Imports nothing else of the compiler but its
numeric library's text."""
