"""Tools, inserts, stock and the machine: the tables every stage reads.

No heavy imports here: the interpreter and the simulator load this on their fast path.

Files (TOML, documented in README):

* the **machine file** (``--machine``): rapid rates, reference point, spindle limit, default
  feed, step limit, G54-G59 origins and offset registers;
* the **tool library** (``--tools``): tools with their ISO insert, holder, tip code and cutting
  data. The default library ships in ``hnc_cam/data/tools.toml`` and also fills the default
  machine's offset registers, so programs we generate simulate with the right radii.

Units: mm, mm/min, rpm, seconds. X values in the files are **diameters** (as on the control's
offset page); internally everything is radius.
"""
from __future__ import annotations

import math
import re
from dataclasses import dataclass, field, replace
from importlib import resources
from pathlib import Path
from typing import Any, Mapping, Optional

from .errors import StockError, ToolError
from .schema import Key, check_table, key_line, parse_toml, place, read_toml

# --------------------------------------------------------------------------------------------
# ISO 1832 turning inserts
# --------------------------------------------------------------------------------------------

#: shape letter -> (included nose angle in degrees, description)
ISO_SHAPES: dict[str, tuple[float, str]] = {
    "C": (80.0, "80 deg rhombic"),
    "D": (55.0, "55 deg rhombic"),
    "E": (75.0, "75 deg rhombic"),
    "M": (86.0, "86 deg rhombic"),
    "V": (35.0, "35 deg rhombic"),
    "K": (55.0, "55 deg parallelogram"),
    "T": (60.0, "triangle"),
    "W": (80.0, "80 deg trigon"),
    "S": (90.0, "square"),
    "R": (360.0, "round"),
}
#: clearance letter -> normal clearance angle in degrees
ISO_CLEARANCE: dict[str, float] = {"A": 3, "B": 5, "C": 7, "D": 15, "E": 20, "F": 25, "G": 30,
                                   "N": 0, "P": 11}

_ISO_RE = re.compile(r"^([A-Z])([A-Z])([A-Z])([A-Z])(\d{2})(\d{2}|T\d)(\d{2}|M0)([A-Z0-9-]*)$")


@dataclass(frozen=True)
class Insert:
    """The cutting part of a tool.

    ``kind`` is ``turn`` (ISO turning insert), ``thread`` (a profile insert with ``angle``),
    ``groove`` (a square-ended grooving insert of ``width``) or ``drill`` (a twist, spot or
    centre drill: ``width`` its diameter, ``angle`` its point angle, ``edge_length`` its
    flute length; code ``DRILL<d>[-<point angle>][L<flute length>]``, e.g. ``DRILL10-118L60``).
    """
    code: str
    kind: str = "turn"
    shape: str = "C"
    nose_angle: float = 80.0  # included angle of the cutting corner, deg
    clearance: float = 0.0  # deg
    edge_length: float = 12.0  # mm, length of each cutting edge
    nose_radius: float = 0.8  # mm
    angle: float = 60.0  # thread profile angle (thread inserts), deg
    width: float = 0.0  # groove width (grooving inserts), mm

    @staticmethod
    def parse(code: str, nose_radius: float | None = None) -> "Insert":
        """Parse an ISO turning insert code (``CNMG120408``), or a threading (``16ER1.5ISO``,
        ``16IR1.5ISO``, ``16ERA60``), grooving (``GROOVE3.0`` / ``N123G2-0300``) or drill
        (``DRILL10-118L60``) code.

        An explicit ``nose_radius`` overrides the code's.
        """
        c = code.strip().upper().replace(" ", "")
        m = _ISO_RE.match(c)
        if m:
            shape, clr, _tol, _typ, size, _thick, rad, _rest = m.groups()
            if shape not in ISO_SHAPES:
                raise ToolError(f"insert {code!r}: unknown ISO shape letter {shape!r}")
            if clr not in ISO_CLEARANCE:
                raise ToolError(f"insert {code!r}: unknown ISO clearance letter {clr!r}")
            r = 0.0 if rad == "M0" else int(rad) / 10.0
            if nose_radius is not None:
                r = float(nose_radius)
            return Insert(code=c, kind="turn", shape=shape, nose_angle=ISO_SHAPES[shape][0],
                          clearance=ISO_CLEARANCE[clr], edge_length=float(int(size)),
                          nose_radius=r)
        m = re.match(r"^(\d{2})([EI])R(?:(\d+(?:\.\d+)?)(ISO|UN|W)?|A(\d+))$", c)
        if m:
            size, _ei, pitch, std, ang = m.groups()
            angle = 55.0 if std == "W" else float(ang) if ang else 60.0
            r = 0.125 * float(pitch) if pitch else 0.05  # ISO 68 root radius ~ P/8
            if nose_radius is not None:
                r = float(nose_radius)
            return Insert(code=c, kind="thread", shape="T", nose_angle=angle, clearance=0.0,
                          edge_length=float(size), nose_radius=r, angle=angle)
        m = re.match(r"^DRILL(\d+(?:\.\d+)?)(?:-(\d+(?:\.\d+)?))?(?:L(\d+(?:\.\d+)?))?$", c)
        if m:
            d = float(m.group(1))
            ang = float(m.group(2)) if m.group(2) else 118.0
            flute = float(m.group(3)) if m.group(3) else 5.0 * d
            if not (d > 0 and 0 < ang < 180 and flute > 0):
                raise ToolError(f"insert {code!r}: a drill needs a diameter above 0, a point "
                                f"angle between 0 and 180 deg and a flute length above 0")
            return Insert(code=c, kind="drill", shape="DR", nose_angle=ang, clearance=0.0,
                          edge_length=flute, nose_radius=0.0, angle=ang, width=d)
        m = re.match(r"^(?:GROOVE(\d+(?:\.\d+)?)|N\d{3}[A-Z]\d?-(\d{4}))", c)
        if m:
            w = float(m.group(1)) if m.group(1) else int(m.group(2)) / 100.0
            r = 0.2 if nose_radius is None else float(nose_radius)
            return Insert(code=c, kind="groove", shape="G", nose_angle=90.0, clearance=0.0,
                          edge_length=max(10.0, w), nose_radius=r, width=w)
        raise ToolError(f"insert {code!r}: not an ISO turning insert code (like CNMG120408), "
                        f"a threading insert (like 16ER1.5ISO) or a grooving insert (like GROOVE3.0)")


#: holder ISO code letter 3 (style) -> approach (lead) angle kappa_r in degrees
HOLDER_APPROACH: dict[str, float] = {"A": 90, "B": 75, "D": 45, "F": 90, "G": 90, "J": 93,
                                     "K": 75, "L": 95, "N": 63, "Q": 107.5, "S": 45, "T": 60,
                                     "U": 93, "V": 72.5}


@dataclass(frozen=True)
class Tool:
    """A tool in the library: where it sits (number, offset register), what cuts, how."""
    number: int
    register: int
    name: str
    insert: Insert
    tip: int = 3  # tip direction code 0-9 (fig. 3.3.44)
    hand: str = "R"
    holder: str = ""
    approach: float = 95.0  # holder approach angle kappa_r, deg
    #: turn | bore | thread | groove | groove_id (an inside grooving bar) | groove_face (an
    #: axial grooving blade for ring grooves in a face) | part (a parting blade) | drill |
    #: center_drill
    kind: str = "turn"
    uses: tuple[str, ...] = ("rough", "finish")
    depth: float = 1.5  # roughing depth of cut per side, mm
    feed_rough: float = 0.25  # mm/rev
    feed_finish: float = 0.1  # mm/rev
    vc_rough: float = 180.0  # m/min
    vc_finish: float = 220.0  # m/min
    rpm: float = 0.0  # fixed speed (threading), rpm
    min_bore: float = 0.0  # smallest bore diameter a boring bar enters, mm
    max_rpm: float = 0.0  # the tool's own spindle limit (0: the machine's), rpm
    dwell_rev: float = 2.0  # spindle revolutions at the bottom of a groove plunge
    #: a parting blade's reach below the stock's surface, an inside grooving bar's beyond
    #: the bore (radial), a boring bar's along Z from the face (mm; 0 = not limited)
    max_depth: float = 0.0
    x_offset: float = 0.0  # diameter
    z_offset: float = 0.0
    #: an axial grooving blade's range (its curvature): the face groove's inner diameter
    #: at least ``min_diameter``, its outer diameter at most ``max_diameter`` (mm)
    min_diameter: float = 0.0
    max_diameter: float = 0.0

    @property
    def nose_radius(self) -> float:
        return self.insert.nose_radius

    @property
    def is_drill(self) -> bool:
        """A twist drill or a centre (spot) drill: it cuts on the axis with its point."""
        return self.kind in DRILL_KINDS

    @property
    def diameter(self) -> float:
        """A drill's diameter (mm; 0 for other tools)."""
        return self.insert.width if self.insert.kind == "drill" else 0.0

    @property
    def point_angle(self) -> float:
        """A drill's included point angle (deg)."""
        return self.insert.angle

    @property
    def flute_length(self) -> float:
        """How deep a drill can go: its flute length (mm)."""
        return self.insert.edge_length


#: the tool kinds that drill on the axis
DRILL_KINDS = ("drill", "center_drill")


# --------------------------------------------------------------------------------------------
# Offset registers and the machine
# --------------------------------------------------------------------------------------------

@dataclass(frozen=True)
class Register:
    """One offset register as on the control's offset page (X values as diameters)."""
    number: int
    x: float = 0.0  # geometry offset, diameter
    z: float = 0.0
    x_wear: float = 0.0  # diameter
    z_wear: float = 0.0
    radius: float = 0.0  # nose radius
    tip: int = 0  # tip direction code 0-9
    insert: Insert | None = None  # for the simulator's tool outline, when known
    approach: float = 95.0
    kind: str = "turn"
    min_bore: float = 0.0  # an inside tool's smallest bore (its bar's head across the bore)

    @property
    def x_total_radius(self) -> float:
        return (self.x + self.x_wear) / 2.0

    @property
    def z_total(self) -> float:
        return self.z + self.z_wear


SHARP = Register(number=0)

#: the running clearance a boring bar's head keeps from the bore's far wall, mm: the planner
#: faces a flat bottom no nearer the axis than its head allows with it, and verification
#: counts a bar's reach with it (its head ``min_bore`` + this across the bore)
BAR_CLEARANCE = 1.0

#: what an M code of the machine's PLC does, as the interpreter models it: spindle direction
#: (before the block's motion) and stop (after it), coolant on (before) / off (after), tool
#: change and "other" (acts, no effect on the toolpath), optional stop (after; the run
#: continues, as with the optional-stop switch off)
M_MEANINGS = ("spindle_cw", "spindle_ccw", "spindle_stop", "coolant_on", "coolant_off",
              "tool_change", "optional_stop", "other")
#: M codes fixed by the CNC (manual §3.1.1): program stop, end, end and rewind, call, return
CNC_M_CODES = (0, 2, 30, 98, 99)
#: the standard PLC's M codes (manual table 3.1) plus M08 (flood coolant on most lathes)
DEFAULT_M_CODES = {3: "spindle_cw", 4: "spindle_ccw", 5: "spindle_stop", 6: "tool_change",
                   7: "coolant_on", 8: "coolant_on", 9: "coolant_off"}
#: a machine file register with ``edge = d`` (d > 1) is kept under EDGE_KEY * d + its number
#: (SINUMERIK ``T t D d``); edge 1 is the register itself
EDGE_KEY = 100
#: machine file [limits] key -> Machine field
LIMIT_KEYS = {"moves": "move_limit", "cycle_passes": "pass_limit", "calls": "call_limit",
              "program_bytes": "program_bytes", "line_chars": "line_chars"}


@dataclass(frozen=True)
class Machine:
    """Machine parameters. Rapid rates are per axis in mm/min (X as radius motion)."""
    name: str = "HNC-21T"
    rapid_x: float = 4000.0
    rapid_z: float = 8000.0
    reference: tuple[float, float] = (100.0, 150.0)  # (x radius, z) machine coordinates
    max_rpm: float = 3000.0
    default_feed: float = 100.0  # mm/min, used (with a warning) before any F
    step_limit: int = 2_000_000  # statements executed before the step-limit alarm
    tool_change: tuple[float, float] = (50.0, 100.0)  # (x radius, z) work coordinates
    diameter_mode: bool = True  # power-on G36 (True) or G37 radius programming (False)
    work_offsets: dict[str, tuple[float, float]] = field(
        default_factory=lambda: {f"G{n}": (0.0, 0.0) for n in range(54, 60)})
    registers: dict[int, Register] = field(default_factory=dict)
    #: the PLC's M codes (number -> one of :data:`M_MEANINGS`); M00 M02 M30 M98 M99 are the
    #: CNC's own and not listed (manual §3.1)
    m_codes: dict[int, str] = field(default_factory=lambda: dict(DEFAULT_M_CODES))
    # [limits]: what one program run may produce; far above any real program, they turn a
    # runaway program into an alarm within seconds and bounded memory
    move_limit: int = 500_000  # moves in the toolpath
    pass_limit: int = 10_000  # passes (levels, repetitions) of one cycle block
    call_limit: int = 1_000_000  # subprogram entries (M98/G65 calls and their L repetitions)
    program_bytes: int = 64 * 1024 * 1024  # size of a program file or text
    line_chars: int = 65_536  # characters in one line
    #: the controller's dialect (``hnc_cam.dialect`` name); None = hnc21t
    controller: Optional[str] = None
    #: FANUC parameter 3401#0: "standard" (X20 = 0.020 mm) or "calculator" (X20 = 20 mm)
    decimal_point: str = "standard"
    block_delete: bool = False  # the block-delete switch: "/" blocks skipped when on
    #: [parameters]: the control's parameters a dialect's cycles read (e.g. g71_depth = 2.0)
    parameters: dict[str, Any] = field(default_factory=dict)
    #: [chuck] max_rpm: the chuck's rated speed (rpm; 0 = not given); the planner's spindle
    #: limits are the lowest of this, ``max_rpm`` and the tool's
    chuck_max_rpm: float = 0.0
    #: [chuck] jaws: the diameters they clamp (min, max), their length along Z and their
    #: height above the gripped diameter (mm); ``grip``: how much of the stock's left end
    #: they hold (mm; 0 = not given: the jaws are not modelled)
    chuck_clamp: tuple[float, float] = (2.0, 250.0)
    jaw_length: float = 30.0
    jaw_height: float = 25.0
    grip: float = 0.0

    def register(self, number: int) -> Register:
        """Offset register ``number``; one absent from the table is a sharp point."""
        if number == 0:
            return SHARP
        return self.registers.get(number) or Register(number=number)

    def with_registers(self, regs: Mapping[int, Register]) -> "Machine":
        merged = dict(self.registers)
        merged.update(regs)
        return replace(self, registers=merged)


def _num(tbl: Mapping[str, Any], key: str, default: float, where: str) -> float:
    v = tbl.get(key, default)
    if isinstance(v, bool) or not isinstance(v, (int, float)):
        raise ToolError(f"{where}: {key} must be a number, got {v!r}")
    return float(v)


def _bool(tbl: Mapping[str, Any], key: str, default: bool, where: str) -> bool:
    v = tbl.get(key, default)
    if not isinstance(v, bool):
        raise ToolError(f"{where}: {key} must be true or false, got {v!r}")
    return v


def _xz(tbl: Mapping[str, Any], key: str, default: tuple[float, float], where: str,
        x_is_diameter: bool = True) -> tuple[float, float]:
    v = tbl.get(key)
    if v is None:
        return default
    if not isinstance(v, Mapping):
        raise ToolError(f"{where}: {key} must be a table {{x = .., z = ..}}")
    x = _num(v, "x", default[0] * (2 if x_is_diameter else 1), f"{where}.{key}")
    z = _num(v, "z", default[1], f"{where}.{key}")
    return (x / 2 if x_is_diameter else x, z)


def _load_toml_text(path: str | Path | None, default_name: str) -> tuple[dict, str, str]:
    """``(data, where, text)`` of a TOML file or the bundled default; unreadable, not UTF-8,
    binary or invalid TOML is a :class:`ToolError` with the place."""
    if path is None:
        text = resources.files("hnc_cam").joinpath("data", default_name).read_text("utf-8")
        where = f"<default {default_name}>"
        return parse_toml(text, where, ToolError), where, text
    data, text = read_toml(str(path), ToolError)
    return data, str(path), text


def _load_toml(path: str | Path | None, default_name: str) -> tuple[dict, str]:
    data, where, _text = _load_toml_text(path, default_name)
    return data, where


def parse_register(tbl: Mapping[str, Any], where: str) -> Register:
    n = tbl.get("number")
    if not isinstance(n, int) or not 0 < n < 100:
        raise ToolError(f"{where}: register number must be an integer 1-99, got {n!r}")
    tip = tbl.get("tip", 0)
    if not isinstance(tip, int) or not 0 <= tip <= 9:
        raise ToolError(f"{where}: tip direction code must be 0-9, got {tip!r}")
    ins = None
    if "insert" in tbl:
        ins = Insert.parse(str(tbl["insert"]), tbl.get("radius"))
    radius = _num(tbl, "radius", ins.nose_radius if ins else 0.0, where)
    if radius < 0:
        raise ToolError(f"{where}: nose radius must not be negative")
    return Register(number=n, x=_num(tbl, "x", 0.0, where), z=_num(tbl, "z", 0.0, where),
                    x_wear=_num(tbl, "x_wear", 0.0, where), z_wear=_num(tbl, "z_wear", 0.0, where),
                    radius=radius, tip=tip, insert=ins,
                    approach=_num(tbl, "approach", 95.0, where),
                    kind=str(tbl.get("kind", ins.kind if ins else "turn")))


_XZ = {"x": Key("float"), "z": Key("float")}
#: the machine file's keys (see :mod:`hnc_cam.schema`): unknown keys, types and ranges are
#: one line ``FILE:LINE: ...`` with a did-you-mean
MACHINE_FILE_SCHEMA = {
    "": {"use_tool_library": Key("bool"), "machine": Key("table"), "work_offsets": Key("table"),
         "register": Key("any"), "m_codes": Key("table"), "limits": Key("table"),
         "controller": Key("str", choices=("hnc21t", "fanuc0it", "haas", "siemens802")),
         "decimal_point": Key("str", choices=("standard", "calculator")),
         "block_delete": Key("bool"), "parameters": Key("table"), "chuck": Key("table")},
    "chuck": {"max_rpm": Key("float", lo=0, lo_open=True, hi=100_000, unit="rpm"),
              "clamp_min": Key("float", lo=0, hi=5000, unit="mm"),
              "clamp_max": Key("float", lo=0, lo_open=True, hi=5000, unit="mm"),
              "jaw_length": Key("float", lo=0, lo_open=True, hi=1000, unit="mm"),
              "jaw_height": Key("float", lo=0, lo_open=True, hi=1000, unit="mm"),
              "grip": Key("float", lo=0, hi=1000, unit="mm")},
    "machine": {"name": Key("str"), "rapid_x": Key("float", lo=0, lo_open=True, unit="mm/min"),
                "rapid_z": Key("float", lo=0, lo_open=True, unit="mm/min"),
                "reference": Key("table"), "max_rpm": Key("float", lo=0, lo_open=True, unit="rpm"),
                "default_feed": Key("float", lo=0, lo_open=True, unit="mm/min"),
                "step_limit": Key("int", lo=1, unit="statements"), "tool_change": Key("table"),
                "diameter_mode": Key("bool")},
    "machine.reference": _XZ,
    "machine.tool_change": _XZ,
    "limits": {"moves": Key("int", lo=1, hi=100_000_000, unit="moves"),
               "cycle_passes": Key("int", lo=1, hi=10_000_000, unit="passes"),
               "calls": Key("int", lo=1, hi=10_000_000_000, unit="runs"),
               "program_bytes": Key("int", lo=1, hi=2 ** 31, unit="bytes"),
               "line_chars": Key("int", lo=1, hi=2 ** 24, unit="characters")},
    "register": {"number": Key("int", lo=1, hi=99), "x": Key("float"), "z": Key("float"),
                 "x_wear": Key("float"), "z_wear": Key("float"), "radius": Key("float", lo=0),
                 "tip": Key("int", lo=0, hi=9), "insert": Key("str"), "approach": Key("float"),
                 "kind": Key("str"), "edge": Key("int", lo=1, hi=9)},
}


def _check_machine_file(data: Mapping[str, Any], where: str, text: str) -> None:
    """Check every key of a machine file against :data:`MACHINE_FILE_SCHEMA` (and the
    ``[work_offsets]``/``[m_codes]`` names); the first problem is a :class:`ToolError`
    ``FILE:LINE: ...``."""
    S = MACHINE_FILE_SCHEMA
    check_table(data, S[""], where, text=text, error=ToolError)
    m = data.get("machine")
    if isinstance(m, Mapping):
        check_table(m, S["machine"], where, text=text, table="machine", error=ToolError)
        for k in ("reference", "tool_change"):
            if isinstance(m.get(k), Mapping):
                check_table(m[k], S[f"machine.{k}"], where, text=text, table="machine",
                            error=ToolError, label=f"machine.{k}")
    lim = data.get("limits")
    if isinstance(lim, Mapping):
        check_table(lim, S["limits"], where, text=text, table="limits", error=ToolError)
    ch = data.get("chuck")
    if isinstance(ch, Mapping):
        check_table(ch, S["chuck"], where, text=text, table="chuck", error=ToolError)
    wo = data.get("work_offsets")
    if isinstance(wo, Mapping):
        names = {f"G{n}": Key("table") for n in range(54, 60)}
        names.update({k.lower(): v for k, v in names.items()})
        check_table(wo, names, where, text=text, table="work_offsets", error=ToolError)
        for k, v in wo.items():
            check_table(v, _XZ, where, text=text, table="work_offsets", error=ToolError,
                        label=f"work_offsets.{k}")
    mc = data.get("m_codes")
    if isinstance(mc, Mapping):
        for k in mc:
            if not re.fullmatch(r"[Mm]\d{1,2}", str(k)):
                n = key_line(text, "m_codes", str(k))
                raise ToolError(f"{place(where, n)}: m_codes: '{k}' is not an M code "
                                f"(write M08 = \"coolant_on\")")
        check_table(mc, {str(k): Key("str", choices=M_MEANINGS) for k in mc}, where, text=text,
                    table="m_codes", error=ToolError)
    regs = data.get("register")
    if isinstance(regs, list):
        for i, r in enumerate(regs):
            check_table(r, S["register"], where, text=text, table="register", index=i,
                        error=ToolError, label=f"register[{i}]")


def _parameters(tbl: Any, where: str, text: str) -> dict[str, Any]:
    """The ``[parameters]`` table: name -> a number or true/false (the dialect's cycles say
    which names they read and check the values)."""
    out: dict[str, Any] = {}
    for k, v in (tbl or {}).items():
        if not isinstance(v, (bool, int, float)):
            n = key_line(text, "parameters", str(k))
            raise ToolError(f"{place(where, n)}: parameters.{k} must be a number "
                            f"or true/false, got {v!r}")
        out[str(k)] = v
    return out


def _m_codes(tbl: Any, where: str) -> dict[int, str]:
    """The default M codes updated by the machine file's ``[m_codes]`` (``M08 = "coolant_on"``)."""
    out = dict(DEFAULT_M_CODES)
    if tbl is None:
        return out
    if not isinstance(tbl, Mapping):
        raise ToolError(f"{where}: [m_codes] must be a table such as M08 = \"coolant_on\"")
    for k, v in tbl.items():
        m = re.fullmatch(r"[Mm](\d{1,2})", str(k))
        if m is None:
            raise ToolError(f"{where}: m_codes.{k}: a key is an M code M00-M99, such as M08")
        n = int(m.group(1))
        if n in CNC_M_CODES:
            raise ToolError(f"{where}: m_codes.{k}: M{n:02d} is fixed by the CNC (manual 3.1.1), "
                            f"not a PLC code")
        if v not in M_MEANINGS:
            raise ToolError(f"{where}: m_codes.{k} = {v!r}: the meaning must be one of "
                            f"{', '.join(M_MEANINGS)}")
        out[n] = v
    return out


def _limits(tbl: Any, where: str) -> dict[str, int]:
    """The machine file's ``[limits]`` as Machine fields (positive integers)."""
    if tbl is None:
        return {}
    if not isinstance(tbl, Mapping):
        raise ToolError(f"{where}: [limits] must be a table")
    out = {}
    for k, v in tbl.items():
        if k not in LIMIT_KEYS:
            raise ToolError(f"{where}: limits.{k}: unknown key (known: {', '.join(LIMIT_KEYS)})")
        if isinstance(v, bool) or not isinstance(v, int) or v <= 0:
            raise ToolError(f"{where}: limits.{k} must be a positive integer, got {v!r}")
        out[LIMIT_KEYS[k]] = v
    return out


def _chuck(ch: Mapping[str, Any], base: Machine, where: str, text: str | None) -> dict[str, Any]:
    """The [chuck] jaw keys as Machine fields; a clamping range upside down or a grip longer
    than the jaws is refused with both numbers."""
    lo = float(ch.get("clamp_min", base.chuck_clamp[0]))
    hi = float(ch.get("clamp_max", base.chuck_clamp[1]))
    jl = float(ch.get("jaw_length", base.jaw_length))
    grip = float(ch.get("grip", base.grip))
    if lo >= hi:
        n = key_line(text, "chuck", "clamp_min")
        raise ToolError(f"{place(where, n)}: [chuck] clamp_min {lo:g} mm is not "
                        f"below clamp_max {hi:g} mm")
    if grip > jl:
        n = key_line(text, "chuck", "grip")
        raise ToolError(f"{place(where, n)}: [chuck] grip {grip:g} mm is longer "
                        f"than the jaws (jaw_length {jl:g} mm)")
    return dict(chuck_clamp=(lo, hi), jaw_length=jl,
                jaw_height=float(ch.get("jaw_height", base.jaw_height)), grip=grip)


def with_grip(machine: Machine, grip: float) -> Machine:
    """``machine`` holding the stock ``grip`` mm deep in its jaws (``--grip``); a grip
    longer than the jaws is refused with both numbers."""
    if not (math.isfinite(grip) and grip > 0):
        raise ToolError(f"grip {grip:g} mm: the grip must be a positive number of mm")
    if grip > machine.jaw_length + 1e-9:
        raise ToolError(f"grip {grip:g} mm is longer than the chuck's jaws ({machine.jaw_length:g} "
                        f"mm, the machine file's [chuck] jaw_length)")
    return replace(machine, grip=float(grip))


def load_machine(path: str | Path | None = None, tools: "ToolLibrary | None" = None) -> Machine:
    """Load a machine file (or the embedded default).

    Offset registers: those of the tool library (the default library when ``tools`` is None)
    first, then the machine file's own ``[[register]]`` entries, which win.
    """
    data, where, text = _load_toml_text(path, "machine.toml")
    _check_machine_file(data, where, text)
    m = data.get("machine", {})
    if not isinstance(m, Mapping):
        raise ToolError(f"{where}: [machine] must be a table")
    base = Machine()
    offsets = dict(base.work_offsets)
    for k, v in (data.get("work_offsets") or {}).items():
        key = k.upper()
        if key not in offsets:
            raise ToolError(f"{where}: work_offsets.{k}: only G54-G59 exist")
        offsets[key] = _xz({"o": v}, "o", (0.0, 0.0), f"{where}.work_offsets.{k}")
    step_limit = m.get("step_limit", base.step_limit)
    if not isinstance(step_limit, int) or step_limit <= 0:
        raise ToolError(f"{where}: step_limit must be a positive integer")
    mach = Machine(
        name=str(m.get("name", base.name)),
        rapid_x=_num(m, "rapid_x", base.rapid_x, where),
        rapid_z=_num(m, "rapid_z", base.rapid_z, where),
        reference=_xz(m, "reference", base.reference, where),
        max_rpm=_num(m, "max_rpm", base.max_rpm, where),
        default_feed=_num(m, "default_feed", base.default_feed, where),
        step_limit=step_limit,
        tool_change=_xz(m, "tool_change", base.tool_change, where),
        diameter_mode=_bool(m, "diameter_mode", base.diameter_mode, where),
        work_offsets=offsets,
    )
    for k in ("rapid_x", "rapid_z", "max_rpm", "default_feed"):
        if getattr(mach, k) <= 0:
            raise ToolError(f"{where}: {k} must be positive")
    mach = replace(mach, m_codes=_m_codes(data.get("m_codes"), where), **_limits(data.get("limits"), where),
                   controller=data.get("controller"),
                   decimal_point=data.get("decimal_point", base.decimal_point),
                   block_delete=data.get("block_delete", base.block_delete),
                   parameters=_parameters(data.get("parameters"), where, text),
                   chuck_max_rpm=float((data.get("chuck") or {}).get("max_rpm", 0.0)),
                   **_chuck(data.get("chuck") or {}, base, where, text))
    regs: dict[int, Register] = {}
    use_lib = data.get("use_tool_library", True)
    if use_lib:
        lib = tools if tools is not None else load_tools(None)
        regs.update(lib.registers())
    for i, r in enumerate(data.get("register", []) or []):
        reg = parse_register(r, f"{where}: register[{i}]")
        edge = r.get("edge", 1) if isinstance(r, Mapping) else 1
        if edge != 1:  # edge d of tool t (SINUMERIK T t D d): register EDGE_KEY * d + t
            reg = replace(reg, number=EDGE_KEY * int(edge) + reg.number)
        regs[reg.number] = reg
    return mach.with_registers(regs)


@dataclass(frozen=True)
class ToolLibrary:
    tools: tuple[Tool, ...]
    source: str = "<default tools.toml>"

    def registers(self) -> dict[int, Register]:
        out: dict[int, Register] = {}
        for t in self.tools:
            out[t.register] = Register(number=t.register, x=t.x_offset, z=t.z_offset,
                                       radius=t.nose_radius, tip=t.tip, insert=t.insert,
                                       approach=t.approach, kind=t.kind,
                                       min_bore=t.min_bore)
        return out

    def by_number(self, number: int) -> Tool | None:
        for t in self.tools:
            if t.number == number:
                return t
        return None

    def for_use(self, use: str, kind: str | None = None) -> list[Tool]:
        return [t for t in self.tools if use in t.uses and (kind is None or t.kind == kind)]


#: the keys of a ``[[tool]]`` entry: type, allowed range or values (see :mod:`hnc_cam.schema`)
TOOL_KEYS = {
    "number": Key("int", 1, 99, required=True),
    "register": Key("int", 1, 99),
    "name": Key("str"),
    "insert": Key("str"),  # required, except for a drill given by its diameter
    "radius": Key("float", 0, 10, "mm"),
    "holder": Key("str"),
    "hand": Key("str", choices=("R", "L", "N"), fold=True),
    "tip": Key("int", 0, 9),
    "approach": Key("float", 0, 180, "deg", lo_open=True),
    "kind": Key("str", choices=("turn", "bore", "thread", "groove", "groove_id", "groove_face",
                                "part", "drill", "center_drill")),
    "uses": Key("strs", choices=("rough", "finish", "face", "profile", "thread", "thread_id",
                                 "groove", "groove_id", "groove_face", "part", "drill",
                                 "center")),
    "min_diameter": Key("float", 0, 2000, "mm"),
    "max_diameter": Key("float", 0, 2000, "mm", lo_open=True),
    "diameter": Key("float", 0.1, 200, "mm", lo_open=True),
    "point_angle": Key("float", 30, 179, "deg"),
    "flute_length": Key("float", 0.5, 1000, "mm"),
    "max_depth": Key("float", 0, 500, "mm"),
    "depth": Key("float", 0.01, 20, "mm"),
    "feed_rough": Key("float", 0.01, 2, "mm/rev"),
    "feed_finish": Key("float", 0.01, 2, "mm/rev"),
    "vc_rough": Key("float", 1, 2000, "m/min"),
    "vc_finish": Key("float", 1, 2000, "m/min"),
    "rpm": Key("float", 0, 50000, "rpm"),
    "min_bore": Key("float", 0, 2000, "mm"),
    "max_rpm": Key("float", 0, 50000, "rpm"),
    "dwell_rev": Key("float", 0.5, 20, "rev"),
    "x": Key("float", -2000, 2000, "mm"),
    "z": Key("float", -2000, 2000, "mm"),
}


def _tool_insert(t: Mapping[str, Any], w: str, text: str, index: int, where: str) -> Insert:
    """The insert of a ``[[tool]]`` entry: its ``insert`` code; a drill (``kind = "drill"``
    or ``"center_drill"``) may give ``diameter``, ``point_angle`` (118 deg unless given) and
    ``flute_length`` (5 x diameter unless given) instead, which must agree with its code
    when both are given."""
    kind = t.get("kind")
    drill_keys = [k for k in ("diameter", "point_angle", "flute_length") if k in t]

    def parse(code: str, radius: Any = None, key: str = "insert") -> Insert:
        try:
            return Insert.parse(code, radius)
        except ToolError as e:  # the code's own error, placed at its key
            n = key_line(text, "tool", key, index)
            raise ToolError(f"{place(where, n)}: tool[{index}]: {e}") from None

    if kind not in DRILL_KINDS:
        if drill_keys:
            n = key_line(text, "tool", drill_keys[0], index)
            raise ToolError(f"{place(where, n)}: tool T{t['number']:02d}: "
                            f"{drill_keys[0]} is a drill's key (kind = \"drill\" or "
                            f"\"center_drill\")")
        if "insert" not in t:
            n = key_line(text, "tool", "\0", index)
            raise ToolError(f"{place(where, n)}: tool[{index}]: insert missing")
        ins = parse(str(t["insert"]), t.get("radius"))
        if ins.kind == "drill":
            raise ToolError(f"{w}: insert {ins.code} is a drill: give kind = \"drill\" or "
                            f"\"center_drill\"")
        return ins
    if "insert" in t:
        ins = parse(str(t["insert"]))
        if ins.kind != "drill":
            raise ToolError(f"{w}: a {kind} needs a drill code (DRILL<d>-<angle>L<flute>, e.g. "
                            f"DRILL10-118L60) or diameter = ..., not insert {ins.code}")
    elif "diameter" not in t:
        n = key_line(text, "tool", "\0", index)
        raise ToolError(f"{place(where, n)}: tool[{index}]: a {kind} needs "
                        f"diameter (mm) or a drill code in insert")
    else:
        d = float(t["diameter"])
        ins = parse(f"DRILL{d:g}-{float(t.get('point_angle', 118.0)):g}"
                    f"L{float(t.get('flute_length', 5.0 * d)):g}", key="diameter")
    for key, have in (("diameter", ins.width), ("point_angle", ins.angle),
                      ("flute_length", ins.edge_length)):
        if key in t and abs(float(t[key]) - have) > 1e-9:
            n = key_line(text, "tool", key, index)
            raise ToolError(f"{place(where, n)}: tool T{t['number']:02d}: "
                            f"{key} {float(t[key]):g} disagrees with insert {ins.code} ({have:g})")
    return ins


def load_tools(path: str | Path | None = None) -> ToolLibrary:
    """Load a tool library (or the bundled one). Every ``[[tool]]`` key is checked against
    :data:`TOOL_KEYS`: an unknown key, a wrong type, a value out of range or not among the
    allowed ones is a :class:`ToolError` naming the file and line."""
    data, where, text = _load_toml_text(path, "tools.toml")
    unknown = [k for k in data if k != "tool"]
    if unknown:
        n = key_line(text, "", unknown[0]) or key_line(text, unknown[0], "\0")
        raise ToolError(f"{place(where, n)}: unknown table or key "
                        f"'{unknown[0]}' (a tool library holds [[tool]] entries)")
    entries = data.get("tool")
    if not isinstance(entries, list) or not entries:
        raise ToolError(f"{where}: no [[tool]] entries")
    tools: list[Tool] = []
    seen: set[int] = set()
    for i, t in enumerate(entries):
        check_table(t, TOOL_KEYS, where, text=text, table="tool", index=i, error=ToolError,
                    label=f"tool[{i}]")
        num = t["number"]
        line = key_line(text, "tool", "number", i)
        w = f"{where}:{line}" if line else where
        if num in seen:
            raise ToolError(f"{w}: tool number {num} appears twice")
        seen.add(num)
        w = f"{w}: tool T{num:02d}"
        reg = t.get("register", num)
        ins = _tool_insert(t, w, text, i, where)
        kind = t.get("kind")
        face_keys = [k for k in ("min_diameter", "max_diameter") if k in t]
        if kind != "groove_face" and face_keys:
            n = key_line(text, "tool", face_keys[0], i)
            raise ToolError(f"{place(where, n)}: tool T{num:02d}: "
                            f"{face_keys[0]} is an axial grooving blade's key (kind = "
                            f"\"groove_face\")")
        if kind == "groove_face":
            if ins.kind != "groove":
                n = key_line(text, "tool", "insert", i)
                raise ToolError(f"{place(where, n)}: tool T{num:02d}: a "
                                f"groove_face blade needs a grooving insert (GROOVE<width>, e.g. "
                                f"GROOVE3.0), not {ins.code}")
            if "max_diameter" not in t:
                n = key_line(text, "tool", "\0", i)
                raise ToolError(f"{place(where, n)}: tool T{num:02d}: a "
                                f"groove_face blade needs max_diameter (the largest face groove "
                                f"it cuts, mm)")
            lo, hi = float(t.get("min_diameter", 0.0)), float(t["max_diameter"])
            if lo >= hi:
                n = key_line(text, "tool", "min_diameter", i)
                raise ToolError(f"{place(where, n)}: tool T{num:02d}: "
                                f"min_diameter {lo:g} must be under max_diameter {hi:g}")
            if hi - lo < 2 * ins.width:
                n = key_line(text, "tool", "max_diameter", i)
                raise ToolError(f"{place(where, n)}: tool T{num:02d}: the "
                                f"range {lo:g}-{hi:g} is narrower than the blade ({ins.width:g} "
                                f"mm wide) across a diameter")
        # an axial grooving blade points along -Z, its controlled point the middle of its end
        tip = t.get("tip", 0 if ins.kind == "drill" else 7 if kind == "groove_face" else 3)
        holder = str(t.get("holder", ""))
        approach = t.get("approach")
        if approach is None:
            approach = HOLDER_APPROACH.get(holder[2:3].upper(), 95.0) if len(holder) >= 3 else 95.0
        uses = t.get("uses", ["drill"] if t.get("kind") == "drill" else ["center"]
                     if t.get("kind") == "center_drill" else ["groove_face"]
                     if t.get("kind") == "groove_face" else ["rough", "finish"])
        if isinstance(uses, str):
            uses = [uses]
        tools.append(Tool(
            number=num, register=reg, name=str(t.get("name", f"T{num:02d}")), insert=ins,
            tip=tip, hand=str(t.get("hand", "R")).upper(), holder=holder,
            approach=float(approach), kind=str(t.get("kind", ins.kind)),
            uses=tuple(str(u) for u in uses), depth=_num(t, "depth", 1.5, w),
            feed_rough=_num(t, "feed_rough", 0.25, w), feed_finish=_num(t, "feed_finish", 0.1, w),
            vc_rough=_num(t, "vc_rough", 180.0, w), vc_finish=_num(t, "vc_finish", 220.0, w),
            rpm=_num(t, "rpm", 0.0, w), min_bore=_num(t, "min_bore", 0.0, w),
            max_rpm=_num(t, "max_rpm", 0.0, w), dwell_rev=_num(t, "dwell_rev", 2.0, w),
            max_depth=_num(t, "max_depth", 0.0, w), x_offset=_num(t, "x", 0.0, w), z_offset=_num(t, "z", 0.0, w),
            min_diameter=_num(t, "min_diameter", 0.0, w),
            max_diameter=_num(t, "max_diameter", 0.0, w)))
    return ToolLibrary(tuple(tools), where)


# --------------------------------------------------------------------------------------------
# Stock
# --------------------------------------------------------------------------------------------

_NUM = r"(\d+(?:\.\d*)?|\.\d+)"
_STOCK_RE = re.compile(rf"^{_NUM}(?:/{_NUM})?[xX*]{_NUM}(?:\+{_NUM})?$")


@dataclass(frozen=True)
class Stock:
    """The raw material.

    * ``DxL``: bar of diameter D, length L, right face at Z0, spanning Z in [-L, 0];
    * ``DxL+F``: the same bar with F mm of face stock: right face at Z=+F, spanning [F-L, F]
      (L is the whole length of the piece);
    * ``D/dxL[+F]``: a tube with bore diameter d;
    * ``offset:A``: a near-net blank, the part grown by A mm all round (for G73).
    """
    kind: str  # bar | tube | offset
    diameter: float = 0.0
    bore: float = 0.0
    length: float = 0.0
    face: float = 0.0
    allowance: float = 0.0
    spec: str = ""

    @property
    def z_right(self) -> float:
        return self.face

    @property
    def z_left(self) -> float:
        return self.face - self.length

    @staticmethod
    def parse(spec: str) -> "Stock":
        s = spec.strip()
        if s.lower().startswith("offset:"):
            val = s[7:].strip()
            try:
                a = float(val)
            except ValueError:
                raise StockError(f"stock {spec!r}: offset:A needs a number of mm, got {val!r}") from None
            if not a > 0 or not math.isfinite(a):
                raise StockError(f"stock {spec!r}: the offset must be a positive number of mm")
            return Stock(kind="offset", allowance=a, spec=s)
        m = _STOCK_RE.match(s.replace(" ", ""))
        if not m:
            raise StockError(f"stock {spec!r}: expected DxL, DxL+F, D/dxL[+F] or offset:A "
                             f"(e.g. 50x120+2, 60/20x80, offset:2)")
        d, bore, length, face = m.groups()
        D, L = float(d), float(length)
        b = float(bore) if bore else 0.0
        F = float(face) if face else 0.0
        if D <= 0:
            raise StockError(f"stock {spec!r}: diameter must be positive")
        if L <= 0:
            raise StockError(f"stock {spec!r}: length must be positive")
        if bore is not None and not 0 < b < D:
            raise StockError(f"stock {spec!r}: bore {b:g} must be between 0 and the diameter {D:g}")
        if F >= L:
            raise StockError(f"stock {spec!r}: face stock {F:g} must be less than the length {L:g}")
        return Stock(kind="tube" if bore else "bar", diameter=D, bore=b, length=L, face=F, spec=s)
