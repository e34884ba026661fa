"""The term-folding emitter of :mod:`trikedyn.model.codegen` and spatial algebra over folded values.

A *value* is a float constant, known when the code is generated, or the name of a local variable of the
generated function. Sums of products fold their constants: a product with 0 vanishes, a factor 1 drops, a sum
of one plain name is that name; every other sum becomes one assignment to a fresh local. The spatial
functions follow :mod:`trikedyn.model.spatial` term by term (Featherstone 2008, ch. 2) over such values.
"""

from __future__ import annotations


def term(*vals):
    """A product of values (float constants or variable names) as ``(coefficient, names)``; None if 0."""
    coef, names = 1.0, []
    for v in vals:
        if isinstance(v, float):
            coef *= v
        else:
            names.append(v)
    return None if coef == 0.0 else (coef, tuple(names))


class Emitter:
    """Straight-line code: each non-trivial sum of products becomes one assignment to a fresh local."""

    def __init__(self, indent="    "):
        self.lines, self.count, self.indent, self.loaded = [], 0, indent, set()

    def line(self, text):
        """Append one line of code."""
        self.lines.append(self.indent + text)

    def address(self, array, index):
        """The code of the entry ``array[index]`` (``index`` a tuple of ints)."""
        return f"{array}[{', '.join(str(i) for i in index)}]"

    def load(self, array, *index):
        """The local holding ``array[index]``, loaded at first use."""
        name = array + "_" + "_".join(str(i) for i in index)
        if name not in self.loaded:
            self.loaded.add(name)
            self.line(f"{name} = {self.address(array, index)}")
        return name

    def store(self, array, index, value):
        """Write ``value`` (a value, or an expression's text) into ``array[index]``."""
        self.line(f"{self.address(array, index)} = {value}")

    def sum(self, *terms):
        """The folded sum of ``terms`` (from :func:`term`, None for zero): a constant, a name or a new local."""
        terms = [t for t in terms if t is not None]
        const = sum(c for c, f in terms if not f)
        rest = [(c, f) for c, f in terms if f]
        if not rest:
            return float(const)
        if const == 0.0 and len(rest) == 1 and rest[0][0] == 1.0 and len(rest[0][1]) == 1:
            return rest[0][1][0]
        parts = []
        for c, f in rest:
            body = "*".join(f)
            parts.append(body if c == 1.0 else "-" + body if c == -1.0 else f"{c!r}*{body}")
        if const != 0.0:
            parts.append(repr(const))
        text = " + ".join(parts).replace("+ -", "- ")
        name = f"t{self.count}"
        self.count += 1
        self.line(f"{name} = {text}")
        return name

    def add(self, a, b):
        """The folded ``a + b``."""
        return self.sum(term(a), term(b))

    def dot(self, xs, ys):
        """The folded dot product of two lists of values."""
        return self.sum(*(term(x, y) for x, y in zip(xs, ys, strict=True)))


def cross(em, a, b):
    """The folded ``a x b`` of 3-vectors."""
    return [em.sum(term(a[1], b[2]), term(-1.0, a[2], b[1])),
            em.sum(term(a[2], b[0]), term(-1.0, a[0], b[2])),
            em.sum(term(a[0], b[1]), term(-1.0, a[1], b[0]))]


def xform_motion(em, e, r, m):
    """``X m``: angular ``E w``, linear ``E (v - r x w)``."""
    rw = cross(em, r, m[:3])
    lin = [em.sum(term(m[3 + i]), term(-1.0, rw[i])) for i in range(3)]
    return [em.dot(e[i], m[:3]) for i in range(3)] + [em.dot(e[i], lin) for i in range(3)]


def xform_force_inv(em, e, r, f):
    """``X^T f``: moment ``E^T n + r x (E^T f)``, force ``E^T f``."""
    et = [[e[j][i] for j in range(3)] for i in range(3)]
    n = [em.dot(et[i], f[:3]) for i in range(3)]
    fl = [em.dot(et[i], f[3:]) for i in range(3)]
    rf = cross(em, r, fl)
    return [em.add(n[i], rf[i]) for i in range(3)] + fl


def cross_motion(em, v, m):
    """The folded ``v x m`` of motion vectors."""
    return cross(em, v[:3], m[:3]) + [
        em.sum(term(v[1], m[5]), term(-1.0, v[2], m[4]), term(v[4], m[2]), term(-1.0, v[5], m[1])),
        em.sum(term(v[2], m[3]), term(-1.0, v[0], m[5]), term(v[5], m[0]), term(-1.0, v[3], m[2])),
        em.sum(term(v[0], m[4]), term(-1.0, v[1], m[3]), term(v[3], m[1]), term(-1.0, v[4], m[0]))]


def cross_force(em, v, f):
    """The folded ``v x* f``."""
    return [
        em.sum(term(v[1], f[2]), term(-1.0, v[2], f[1]), term(v[4], f[5]), term(-1.0, v[5], f[4])),
        em.sum(term(v[2], f[0]), term(-1.0, v[0], f[2]), term(v[5], f[3]), term(-1.0, v[3], f[5])),
        em.sum(term(v[0], f[1]), term(-1.0, v[1], f[0]), term(v[3], f[4]), term(-1.0, v[4], f[3])),
    ] + cross(em, v[:3], f[3:])


def inertia_times(em, m, h, ibar, a):
    """``I a`` for the inertia ``(m, h, Ibar)``."""
    w, v = a[:3], a[3:]
    hv = cross(em, h, v)
    hw = cross(em, h, w)
    return ([em.sum(*(term(ibar[i][k], w[k]) for k in range(3)), term(hv[i])) for i in range(3)]
            + [em.sum(term(m, v[i]), term(-1.0, hw[i])) for i in range(3)])


def inertia_to_parent(em, e, r, m, h, ibar):
    """``X^T I X`` of a child inertia: the first moment and rotational inertia it adds at the parent origin."""
    y = [em.dot([e[k][i] for k in range(3)], h) for i in range(3)]
    hp = [em.sum(term(y[i]), term(m, r[i])) for i in range(3)]
    tmp = [[em.dot(ibar[i], [e[k][j] for k in range(3)]) for j in range(3)] for i in range(3)]
    diag = em.sum(*(term(r[k], y[k]) for k in range(3)), *(term(hp[k], r[k]) for k in range(3)))
    out = [[None] * 3 for _ in range(3)]
    for i in range(3):
        for j in range(3):
            out[i][j] = em.sum(*(term(e[k][i], tmp[k][j]) for k in range(3)), term(-1.0, y[i], r[j]),
                               term(-1.0, r[i], hp[j]), term(diag) if i == j else None)
    return hp, out
