"""The equations as Mech prints them: Φ, Φ_q, ν, γ labelled by constraint (text, LaTeX)."""
from __future__ import annotations

import os

import sympy as sp
from sympy.printing.mathematica import MCodePrinter



def _numeric(expr, model, numeric):
    if not numeric:
        return expr
    subs = {sym: sp.Float(val, 6) if val != int(val) else sp.Integer(int(val))
            for sym, val in model.params.values()}
    return expr.subs(subs)


class _MechPrinter(MCodePrinter):
    """Mathematica syntax as Mech prints it: Cos[Th3], Sqrt[...], a space for a product."""

    def _print_Pow(self, expr):
        if expr.exp == sp.Rational(1, 2):
            return f"Sqrt[{self._print(expr.base)}]"
        if expr.exp == -sp.Rational(1, 2):
            return f"1/Sqrt[{self._print(expr.base)}]"
        return super()._print_Pow(expr)

    def _print_sign(self, expr):
        # sympy's Mathematica printer knows no sign(): it printed "sign[T - 1]"
        return f"Sign[{self._print(expr.args[0])}]"


def mathematica(expr) -> str:
    """``expr`` in Mech's notation: ``9 (-X2 + X3 - 3 Cos[Th2]) Cos[Th3]``."""
    return _MechPrinter().doprint(expr).replace("*", " ")


_LATEX_SPECIAL = {"\\": r"\textbackslash{}", "_": r"\_", "#": r"\#", "%": r"\%",
                  "&": r"\&", "{": r"\{", "}": r"\}", "$": r"\$", "^": r"\^{}", "~": r"\~{}"}


def _latex_text(text: str) -> str:
    """Plain text (a constraint label) made safe inside \\text{...}."""
    return "".join(_LATEX_SPECIAL.get(ch, ch) for ch in text)


def _shown_path(path: str) -> str:
    """A model file's path as a user typed it: relative to the current folder when it
    lies inside it (examples/quick_return.py), else absolute."""
    try:
        rel = os.path.relpath(path)
    except ValueError:          # another drive (Windows)
        return path
    return path if rel.startswith("..") else rel


COMMENT_COLUMN = 64      # labels start here unless the expression is longer


def _rows(pairs, indent="  "):
    """Lines ``[i]  text    # label``, the labels aligned in one column; a row too long for
    the column gets its label on a line of its own above it."""
    width = max((len(t) + len(x) + 2 for (t, x), _ in pairs
                 if len(t) + len(x) + 2 <= COMMENT_COLUMN), default=0)
    out = []
    for (tag, text), label in pairs:
        row = f"{tag}  {text}"
        if not label:
            out.append(f"{indent}{row}")
        elif len(row) <= COMMENT_COLUMN:
            out.append(f"{indent}{row.ljust(width)}    # {label}")
        else:
            out.append(f"{indent}{tag}  # {label}")
            out.append(f"{indent}{' ' * len(tag)}  {text}")
    return out


def equations_text(model, numeric=False, latex=False, mathematica_style=False) -> str:
    """Φ, Φ_q, ν = −Φ_t and γ, each row labelled with its constraint, laid out to be read
    beside Mech's printouts (Constraints, Jacobian, VelocityTerms = Φ_t = −ν,
    AccelerationTerms = −γ). ``mathematica_style`` prints Mech's own notation
    (``Cos[Th3]``); ``numeric`` substitutes the parameter defaults (6 digits, as Mech)."""
    eq = model.equations()
    if getattr(model, "stages", None):
        return _staged_text(model, numeric, latex, mathematica_style)
    if latex:
        return _equations_latex(model, eq, numeric)
    fmt = mathematica if mathematica_style else sp.sstr

    def show(e):
        return fmt(_numeric(sp.sympify(e), model, numeric))

    m, n = eq.phi_q.shape
    w = len(str(m))

    def tag(i):
        return f"[{i + 1:>{w}}]"

    lines = [f"Model {model.name}: {m} equations in {n} coordinates"
             + (f"  [{_shown_path(model.source)}]" if getattr(model, "source", None) else ""),
             "  q   = (" + ", ".join(map(str, eq.q)) + ")",
             "  qd  = (" + ", ".join(map(str, eq.qd)) + ")",
             "  qdd = (" + ", ".join(map(str, eq.qdd)) + ")"]
    if model.params:
        values = ", ".join(f"{k} = {v:g}" for k, v in model.param_defaults.items())
        lines.append(f"  parameters: {values}" + ("  (substituted)" if numeric
                                                  else "  (kept as symbols)"))
    lines += ["", "Phi(q, t) = 0, one row per equation        [Mech: Constraints[All]]"]
    lines += _rows([((tag(i), f"{show(eq.phi[i])} = 0"), eq.labels[i]) for i in range(m)])

    # Φ_q: the sparsity pattern as a table, then every entry that is not a plain number
    lines += ["", f"Phi_q, {m} x {n}; '#' marks an entry listed below   "
                  "[Mech: Jacobian[All, All]]"]
    names = [str(c) for c in eq.q]
    cells = [[("." if eq.phi_q[i, j] == 0 else show(eq.phi_q[i, j])
               if eq.phi_q[i, j].is_number else "#") for j in range(n)] for i in range(m)]
    cells = [[c if len(c) <= max(len(names[j]), 3) else "#" for j, c in enumerate(row)]
             for row in cells]
    widths = [max(len(names[j]), *(len(cells[i][j]) for i in range(m))) for j in range(n)]
    lines.append(" " * (6 + w) + "  ".join(nm.rjust(wd) for nm, wd in zip(names, widths)))
    for i in range(m):
        lines.append(f"  {tag(i)}  " + "  ".join(c.rjust(wd) for c, wd in zip(cells[i], widths)))
    keys = [(i, j) for i in range(m) for j in range(n) if cells[i][j] == "#"]
    if keys:
        kw = max(len(f"{i + 1}, {names[j]}") for i, j in keys) + 2
        lines += [f"  {f'[{i + 1}, {names[j]}]'.ljust(kw)}  {show(eq.phi_q[i, j])}"
                  for i, j in keys]

    lines += ["", "nu = -Phi_t: Phi_q qd = nu          [Mech: VelocityTerms[All] = Phi_t = -nu]"]
    lines += _rows([((tag(i), show(eq.nu[i])), eq.labels[i]) for i in range(m)])
    lines += ["", "gamma: Phi_q qdd = gamma            [Mech: AccelerationTerms[All] = -gamma]"]
    lines += _rows([((tag(i), show(eq.gamma[i])), eq.labels[i]) for i in range(m)])
    if model.has_dynamics:          # masses and loads (mechgen.model.forces.dynamics)
        from .forces.dynamics import forces_lines
        short = (lambda e: sp.sstr(_numeric(sp.sympify(e), model, numeric), full_prec=False)) \
            if fmt is sp.sstr else show
        lines += forces_lines(model, eq, short, _rows)
    return "\n".join(lines).rstrip() + "\n"


def _staged_text(model, numeric, latex, mathematica_style) -> str:
    """A model with stages (Mech's TimeSwitch): each stage's system in turn, under a
    heading with its time range (mechgen.model.stages)."""
    times = ", ".join(f"{t:g}" for t in model.switch_times)
    out = []
    for s in model.stages:
        head = (f"Stage {s.number} of {len(model.stages)} '{s.name}': {s.range_text()}  "
                f"(switches at t = {times}; positions continuous, velocities may jump)")
        text = equations_text(model.stage_view(s), numeric, latex, mathematica_style)
        out.append(("% " if latex else "") + head + "\n" + ("" if latex else "=" * len(head)
                                                             + "\n") + text)
    return "\n".join(out)


def _latex_names(eq):
    """Th3 -> \\theta_{3}, X2d -> \\dot{X}_{2}, longitud -> \\mathit{longitud}."""
    import re
    names = {}
    for base, syms in (("", eq.q), ("dot", eq.qd), ("ddot", eq.qdd)):
        for c, s in zip(eq.q, syms):
            found = re.fullmatch(r"(X|Y|Th)(\d+)", c.name)
            if found:
                head = r"\theta" if found.group(1) == "Th" else found.group(1)
                sub = found.group(2)
            else:
                head, sub = (c.name if len(c.name) == 1 else rf"\mathit{{{c.name}}}"), ""
            if base:
                head = rf"\{base}{{{head}}}"
            names[s] = head + (f"_{{{sub}}}" if sub else "")
    for p in eq.params:
        if len(p.name) > 1:
            names[p] = rf"\mathit{{{_latex_text(p.name)}}}"
    return names


def _equations_latex(model, eq, numeric) -> str:
    names = _latex_names(eq)

    def show(e):
        return sp.latex(_numeric(sp.sympify(e), model, numeric), symbol_names=names)

    m, n = eq.phi_q.shape
    out = [f"% Model {model.name}: {m} equations in {n} coordinates",
           "% q = (" + ", ".join(map(str, eq.q)) + ")"]
    if model.params:
        out.append("% parameters: " + ", ".join(f"{k} = {v:g}" for k, v in
                                                 model.param_defaults.items()))

    def block(title, rows):
        out.extend(["", f"% {title}", r"\begin{align*}"])
        out.extend(rows)
        if rows:
            out[-1] = out[-1].rstrip(" \\")
        out.append(r"\end{align*}")

    def label(i):
        return rf"&& \text{{{_latex_text(eq.labels[i])}}} \\"

    block("Phi(q, t) = 0", [rf"\Phi_{{{i + 1}}} &= {show(eq.phi[i])} = 0 {label(i)}"
                            for i in range(m)])
    block("Phi_q (nonzero entries)",
          [rf"\frac{{\partial \Phi_{{{i + 1}}}}}{{\partial {names[eq.q[j]]}}} &= "
           rf"{show(eq.phi_q[i, j])} \\" for i in range(m) for j in range(n)
           if eq.phi_q[i, j] != 0])
    block("nu = -Phi_t", [rf"\nu_{{{i + 1}}} &= {show(eq.nu[i])} {label(i)}" for i in range(m)])
    block("gamma (Phi_q qdd = gamma)", [rf"\gamma_{{{i + 1}}} &= {show(eq.gamma[i])} {label(i)}"
                                        for i in range(m)])
    return "\n".join(out) + "\n"


