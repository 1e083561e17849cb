"""Read a granhydro scene (deal.II ParameterHandler file) for the DEM cross-check.

Only what a DEM run of the scene needs is read: the box, its boundaries, gravity,
the container vibration, the grains, the initial state and the output settings.
Everything else (numerics, dense closure, ...) belongs to the continuum model.

Expressions of the initial state are evaluated by a small safe evaluator (Python's
ast, whitelisted nodes): numbers, x, y, z, t (= 0), pi, the scene's Constants,
+ - * / ^ (**), unary minus, and the functions below. muparser's other syntax
(if-then-else, comparisons) is not supported and is reported as such.
"""

import ast
import math
import os
import sys

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "granhydro_py"))  # tools/granhydro_py: import granhydro
from granhydro.readers import ParameterFileError, flatten_parameters, read_parameters  # noqa: E402

AXES = "xyz"
SIDES = ["x-", "x+", "y-", "y+", "z-", "z+"]

_FUNCS = {
    "sin": np.sin, "cos": np.cos, "tan": np.tan, "asin": np.arcsin, "acos": np.arccos,
    "atan": np.arctan, "sinh": np.sinh, "cosh": np.cosh, "tanh": np.tanh,
    "asinh": np.arcsinh, "acosh": np.arccosh, "atanh": np.arctanh, "exp": np.exp,
    "log": np.log, "ln": np.log, "log10": np.log10, "log2": np.log2, "sqrt": np.sqrt,
    "abs": np.abs, "min": np.minimum, "max": np.maximum, "pow": np.power,
    "sign": np.sign, "floor": np.floor, "ceil": np.ceil,
}
_BINOPS = {ast.Add: np.add, ast.Sub: np.subtract, ast.Mult: np.multiply,
           ast.Div: np.divide, ast.Pow: np.power}


class SceneError(Exception):
    pass


class Expression:
    """A scalar expression of x, y, z (and t = 0) evaluated on numpy arrays."""

    def __init__(self, text, constants=None):
        self.text = text.strip()
        self.constants = dict(constants or {})
        src = self.text.replace("^", "**")
        try:
            self.tree = ast.parse(src, mode="eval")
        except SyntaxError as e:
            raise SceneError("expression '%s' is not understood (%s)" % (self.text, e.msg))
        self._check(self.tree.body)

    def _check(self, node):
        if isinstance(node, ast.Constant):
            if not isinstance(node.value, (int, float)):
                raise SceneError("expression '%s': only numbers are allowed as constants" % self.text)
        elif isinstance(node, ast.Name):
            if node.id not in ("x", "y", "z", "t", "pi") and node.id not in self.constants:
                raise SceneError("expression '%s': unknown name '%s' (allowed: x, y, z, t, pi "
                                 "and Initial state/Constants)" % (self.text, node.id))
        elif isinstance(node, ast.BinOp):
            if type(node.op) not in _BINOPS:
                raise SceneError("expression '%s': operator not supported" % self.text)
            self._check(node.left)
            self._check(node.right)
        elif isinstance(node, ast.UnaryOp):
            if not isinstance(node.op, (ast.USub, ast.UAdd)):
                raise SceneError("expression '%s': operator not supported" % self.text)
            self._check(node.operand)
        elif isinstance(node, ast.Call):
            if not isinstance(node.func, ast.Name) or node.func.id not in _FUNCS or node.keywords:
                raise SceneError("expression '%s': function not supported (allowed: %s)"
                                 % (self.text, ", ".join(sorted(_FUNCS))))
            for a in node.args:
                self._check(a)
        else:
            raise SceneError("expression '%s': only numbers, x, y, z, t, pi, constants, "
                             "+ - * / ^ and functions are supported by the DEM tool" % self.text)

    def __call__(self, x, y, z):
        env = {"x": np.asarray(x, float), "y": np.asarray(y, float), "z": np.asarray(z, float),
               "t": 0.0, "pi": math.pi}
        env.update(self.constants)
        shape = np.broadcast(env["x"], env["y"], env["z"]).shape
        return np.broadcast_to(np.asarray(self._eval(self.tree.body, env), float), shape).copy()

    def _eval(self, node, env):
        if isinstance(node, ast.Constant):
            return float(node.value)
        if isinstance(node, ast.Name):
            return env[node.id]
        if isinstance(node, ast.BinOp):
            return _BINOPS[type(node.op)](self._eval(node.left, env), self._eval(node.right, env))
        if isinstance(node, ast.UnaryOp):
            v = self._eval(node.operand, env)
            return -v if isinstance(node.op, ast.USub) else v
        if isinstance(node, ast.Call):
            return _FUNCS[node.func.id](*[self._eval(a, env) for a in node.args])
        raise SceneError("unreachable")


def read_prm(path):
    """Parse a deal.II parameter file into {'Section/Sub/Name': value} (granhydro.readers;
    SceneError for what it cannot read, e.g. 'include')."""
    try:
        return flatten_parameters(read_parameters(path))
    except ParameterFileError as e:
        raise SceneError(str(e))


def _floats(text, n, default, name):
    parts = [p for p in text.replace(";", ",").split(",") if p.strip()]
    try:
        v = [float(p) for p in parts]
    except ValueError:
        raise SceneError("parameter '%s': '%s' is not a list of numbers" % (name, text))
    return (v + [default] * 3)[:3] if len(v) < 3 else v[:3]


class Scene:
    """What the DEM needs of a granhydro scene (SI units)."""

    def __init__(self, path):
        self.path = path
        p = read_prm(path)
        g = lambda k, d: p.get(k, d)
        self.dim = int(g("Dimension", "2"))
        if self.dim not in (1, 2, 3):
            raise SceneError("parameter 'Dimension' must be 1, 2 or 3")
        if g("Domain/Mesh file", ""):
            raise SceneError("parameter 'Domain/Mesh file': the DEM tool handles boxes only")
        self.lower = _floats(g("Domain/Lower corner", "0, 0, 0"), self.dim, 0.0, "Domain/Lower corner")
        self.upper = _floats(g("Domain/Upper corner", "0.1, 0.1, 0.1"), self.dim, 1.0, "Domain/Upper corner")
        cells = _floats(g("Domain/Cells", "100, 100, 1"), self.dim, 1.0, "Domain/Cells")
        self.cells = [int(c) if d < self.dim else 1 for d, c in enumerate(cells)]
        self.boundary, self.wall_restitution = {}, {}
        for s in SIDES:
            self.boundary[s] = g("Domain/Boundary " + s, "slip wall")
            self.wall_restitution[s] = float(g("Domain/Wall restitution " + s, "1"))
            wv = _floats(g("Domain/Wall velocity " + s, "0, 0, 0"), self.dim, 0.0, "Domain/Wall velocity " + s)
            d = SIDES.index(s) // 2
            if d < self.dim and self.boundary[s] == "outflow":
                raise SceneError("parameter 'Domain/Boundary %s': outflow boundaries are not "
                                 "supported by the DEM tool" % s)
            if d < self.dim and self.boundary[s] == "no-slip wall" and any(wv):
                raise SceneError("parameter 'Domain/Wall velocity %s': moving walls are not "
                                 "supported by the DEM tool" % s)
        self.model = g("Material/Model", "ideal gas")
        if self.model != "granular":
            raise SceneError("parameter 'Material/Model': the DEM cross-check needs 'granular'")
        self.diameter = float(g("Material/Grain diameter", "1e-3"))
        self.density = float(g("Material/Material density", "2600"))
        self.restitution = float(g("Material/Restitution coefficient", "1"))
        self.gravity = _floats(g("Effects/Gravity", "0, 0, 0"), self.dim, 0.0, "Effects/Gravity")
        self.vib_amplitude = float(g("Effects/Vibration amplitude", "0"))
        self.vib_frequency = float(g("Effects/Vibration frequency", "0"))
        self.vib_direction = AXES.index(g("Effects/Vibration direction", "y"))
        if self.vib_amplitude > 0 and self.vib_frequency <= 0:
            raise SceneError("vibration amplitude without a frequency")
        consts = {}
        for c in g("Initial state/Constants", "").split(","):
            if c.strip():
                k, v = c.split("=")
                consts[k.strip()] = float(Expression(v, consts)(0, 0, 0))
        if g("Initial state/Checkpoint", ""):
            raise SceneError("parameter 'Initial state/Checkpoint': a DEM run starts from the expressions")
        self.phi_expr = Expression(g("Initial state/Packing fraction", "0.01"), consts)
        vel = [v for v in g("Initial state/Velocity", "0; 0; 0").split(";")]
        if len(vel) not in (self.dim, 3):
            raise SceneError("parameter 'Initial state/Velocity': one expression per dimension or 3")
        self.vel_expr = [Expression(v, consts) for v in vel] + [Expression("0")] * (3 - len(vel))
        self.temp_expr = Expression(g("Initial state/Temperature", "1e-8"), consts)
        self.end_time = float(g("Time/End time", "0.2"))
        self.output_dir = g("Output/Directory", "output")
        self.output_base = g("Output/Base name", "solution")  # granhydro writes <Directory>/<Base name>_profiles.csv
        self.output_interval = float(g("Output/Interval", "0"))
        pd = g("Output/Profile direction", "auto")
        self.profile_direction = self.dim - 1 if pd == "auto" else AXES.index(pd)
        if self.profile_direction >= self.dim:
            raise SceneError("parameter 'Output/Profile direction' names an unresolved direction")

    # ---- derived -----------------------------------------------------------------
    @property
    def grain_mass(self):
        return self.density * math.pi / 6 * self.diameter ** 3

    @property
    def omega(self):
        return 2 * math.pi * self.vib_frequency

    def container_offset(self, t):
        """s(t) along the vibration direction [m]."""
        return self.vib_amplitude * np.sin(self.omega * np.asarray(t, float)) if self.vib_amplitude > 0 else 0.0 * np.asarray(t, float)

    def container_velocity(self, t):
        return self.vib_amplitude * self.omega * np.cos(self.omega * np.asarray(t, float)) if self.vib_amplitude > 0 else 0.0 * np.asarray(t, float)

    def periodic(self, d):
        return d < self.dim and self.boundary[SIDES[2 * d]] == "periodic"

    def bin_edges(self):
        pd = self.profile_direction
        return np.linspace(self.lower[pd], self.upper[pd], self.cells[pd] + 1)

    def floor_side(self):
        """-1 if gravity points to the lower end of the profile direction, +1 to the upper."""
        return 1 if self.gravity[self.profile_direction] > 0 else -1

    def layered(self, expr, name, coord, lateral_points):
        """Evaluate expr along the profile direction at 'coord'; refuse a lateral dependence."""
        pd = self.profile_direction
        vals = []
        for lp in lateral_points:
            xyz = [np.full_like(coord, lp[d]) for d in range(3)]
            xyz[pd] = coord
            vals.append(expr(*xyz))
        ref = vals[0]
        for v in vals[1:]:
            if np.max(np.abs(v - ref)) > 1e-12 * max(1e-300, np.max(np.abs(ref))):
                raise SceneError("parameter 'Initial state/%s': '%s' depends on a lateral coordinate; "
                                 "the DEM tool takes layered states (a function of the profile "
                                 "coordinate %s only)" % (name, expr.text, AXES[pd]))
        return ref
