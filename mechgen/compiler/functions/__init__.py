"""The straight-line functions of a module: Φ, Φ_q, ν, γ, the points and the outputs
(`equations_code`), the force functions of a model with mass or loads (`forces_code`) and
their fused step with the derivatives (`dynamics_code`), and cam profiles (`profiles_code`,
`profile_derivatives`). Built on `compiler.codegen` and `compiler.solver`."""
