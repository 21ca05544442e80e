"""Part files: a Python module (``parts/*.py``) or a STEP/BREP file -> :class:`LoadedPart`.

The part-file contract (what users write)::

    '''Docstring: what the part is; each parameter with its unit.'''
    from build123d import ...           # or cadquery; imported by the file itself

    STOCK = "40x110+2"                   # optional: str, or a callable(**params) -> str
    THREADS = [Thread(...)]              # optional: list of hnc_cam.geometry.Thread,
                                         #   or a callable(**params) -> list[Thread]

    def part(length: float = 100.0, diameter: float = 30.0):   # keyword args with defaults
        ...                                                       # = the family's parameters
        return solid                     # build123d/CadQuery/OCP solid (one solid)

* Parameters are the keyword arguments of ``part`` that have defaults. Values given on the
  command line (``--set NAME=VALUE``) are parsed as numbers: an int when the default is an
  int and the value is integral, else a float. ``params`` holds every parameter, given or
  defaulted.
* ``STOCK`` uses the stock notation (``DxL``, ``DxL+F``, ``D/dxL[+F]``, ``offset:A``); it is
  checked with :meth:`hnc_cam.tooling.Stock.parse` when the part is loaded.
* ``THREADS`` Z values are in the part's own program coordinates: program zero on the right
  face (Z0), the part toward -Z (``z_start`` the end nearer the right face). ``diameter`` is
  the nominal (major) diameter, ``pitch`` > 0, ``starts`` >= 1 (lead = pitch x starts),
  ``internal`` for a thread in the bore, ``standard``/``angle`` the form (``"metric"``, 60).
  The solid models an external thread at its major diameter and an internal one at the bore
  (about the minor diameter). When the part is loaded each thread is checked against the
  profile (PartError naming the thread): it must lie on the part; an external thread on the
  outside whose largest diameter over the thread is between the minor diameter and the major
  diameter + 0.02 mm; an internal thread inside the bore over its whole length, the bore's
  smallest diameter there under the major diameter and not more than one thread depth
  (radial) under the minor diameter.
* The module is run in a fresh namespace each time the file is loaded (so one process can load
  many variants); ``part()`` is called once per load.
* A plain modelling script without a ``part()`` function is a part without parameters when
  it leaves its solid in a module-level ``part`` (build123d's ``BuildPart`` or its ``.part``)
  or ``result`` (CadQuery's convention).
"""
from __future__ import annotations

import importlib.util
import inspect
import dataclasses
import math
import re
import sys
import zlib
from dataclasses import dataclass, field
from pathlib import Path
from types import ModuleType
from typing import Any, Iterable

from ..errors import HncError, PartError, ProfileError, StockError
from ..geometry.profile import Thread, TurnedProfile
from .sketch import Revolved, deferred

CAD_SUFFIXES = (".step", ".stp", ".brep")


@dataclass
class LoadedPart:
    """A part ready for planning: its profile, default stock, declared threads."""
    profile: TurnedProfile
    stock: str | None
    threads: list[Thread]
    name: str
    params: dict[str, Any] = field(default_factory=dict)
    module: ModuleType | None = None
    path: Path | None = None

    def __getstate__(self) -> dict[str, Any]:
        """Picklable (e.g. to send to a worker process): the module is left behind."""
        state = dict(self.__dict__)
        state["module"] = None
        return state


def parse_set(items: Iterable[str] | None) -> dict[str, str]:
    """``["NAME=VALUE", ...]`` (the CLI's ``--set``) -> ``{"NAME": "VALUE"}``."""
    out: dict[str, str] = {}
    for it in items or []:
        if "=" not in it:
            raise PartError(f"--set {it!r}: expected NAME=VALUE")
        k, v = it.split("=", 1)
        k, v = k.strip(), v.strip()
        if not k.isidentifier():
            raise PartError(f"--set {it!r}: {k!r} is not a parameter name")
        if not v:
            raise PartError(f"--set {it!r}: no value for {k}")
        out[k] = v
    return out


def _import_file(path: Path) -> ModuleType:
    modname = f"hnc_part_{path.stem}_{zlib.crc32(str(path.resolve()).encode()):08x}"
    spec = importlib.util.spec_from_file_location(modname, path)
    if spec is None or spec.loader is None:
        raise PartError(f"{path}: not importable as a Python module")
    mod = importlib.util.module_from_spec(spec)
    sys.modules[modname] = mod  # dataclasses/pickle inside the part file look it up
    try:
        spec.loader.exec_module(mod)
    except HncError:
        sys.modules.pop(modname, None)
        raise
    except Exception as e:  # noqa: BLE001 - any error in a user's file is reported as its own
        sys.modules.pop(modname, None)
        raise PartError(f"{path}: import failed: {type(e).__name__}: {e}") from e
    return mod


@dataclass
class _Imported:
    """A part module as imported, with what it was imported from: the digest of the part
    file and of each helper module of the user's it imported (file -> digest; their names in
    ``sys.modules``)."""
    module: ModuleType
    digest: bytes | None
    helpers: dict[str, bytes | None]
    names: set[str]
    called: bool = False


#: part modules by resolved path: reused while neither the part file nor a helper module it
#: imports changes (a long-lived process, a cluster worker, loads the edited files again)
_MODULE_CACHE: dict[str, _Imported] = {}


def _digest(path: str | Path) -> bytes | None:
    import hashlib
    try:
        return hashlib.blake2b(Path(path).read_bytes(), digest_size=16).digest()
    except OSError:
        return None


_SYSTEM_ROOTS: list[str] = []


def _system_roots() -> list[str]:
    """Folders of installed code (the standard library, site-packages, this package): a
    module there is not a helper of the user's part."""
    if not _SYSTEM_ROOTS:
        import os
        import site
        import sysconfig
        roots = {sysconfig.get_paths().get(k) for k in ("stdlib", "platstdlib", "purelib",
                                                        "platlib")}
        try:
            roots.add(site.getusersitepackages())
        except Exception:  # noqa: BLE001 - no user site
            pass
        roots.add(str(Path(__file__).resolve().parents[1]))
        _SYSTEM_ROOTS.extend(os.path.realpath(r) + os.sep for r in roots if r)
    return _SYSTEM_ROOTS


def _helpers(mod: ModuleType, before: set[str]) -> set[str]:
    """Names in ``sys.modules`` of the user's own modules the part module uses: those that
    appeared while it was imported (or its part() first ran) and those its namespace refers
    to (``import helper``, ``from helper import f``), outside the installed code."""
    import os
    roots = _system_roots()
    names = {n for n in list(sys.modules) if n not in before}
    for v in list(vars(mod).values()):
        if isinstance(v, ModuleType):
            names.add(v.__name__)
        else:
            try:
                m = getattr(v, "__module__", None)
            except Exception:  # noqa: BLE001 - an object whose attributes raise
                continue
            if isinstance(m, str):
                names.add(m)
    out = set()
    for n in names:
        m = sys.modules.get(n)
        f = getattr(m, "__file__", None)
        if m is None or m is mod or not isinstance(f, str) or not f.endswith(".py"):
            continue
        if not os.path.realpath(f).startswith(tuple(roots)):
            out.add(n)
    return out


def _note_helpers(entry: _Imported, names: set[str]) -> None:
    for n in names - entry.names:
        f = getattr(sys.modules.get(n), "__file__", None)
        if f:
            entry.names.add(n)
            entry.helpers[f] = _digest(f)


def load_module(path: str | Path) -> ModuleType:
    """The part module at ``path``, imported again only when the part file or a helper
    module of the user's that it imports has changed (compared by contents, not times)."""
    p = Path(path)
    if not p.exists():
        raise PartError(f"{p}: no such part file")
    _regular(p)
    if p.suffix != ".py":
        raise PartError(f"{p}: a part file is a .py module (or a .step/.stp/.brep file)")
    key = str(p.resolve())
    digest = _digest(p)
    hit = _MODULE_CACHE.get(key)
    if hit is not None and hit.digest == digest and all(
            _digest(f) == d for f, d in hit.helpers.items()):
        return hit.module
    if hit is not None:  # import the changed helpers again with the part
        for n in hit.names:
            sys.modules.pop(n, None)
        del _MODULE_CACHE[key]
    before = set(sys.modules)
    mod = _import_file(p)
    if not callable(getattr(mod, "part", None)):
        _script_part(mod, p)
    entry = _Imported(mod, digest, {}, set())
    _note_helpers(entry, _helpers(mod, before))
    _MODULE_CACHE[key] = entry
    return mod


def _call_part(p: Path, mod: ModuleType, params: dict[str, Any]) -> Any:
    """``mod.part(**params)``; the first call of a freshly imported module also notes the
    helper modules part() imports when it runs."""
    entry = _MODULE_CACHE.get(str(p.resolve()))
    if entry is None or entry.called or entry.module is not mod:
        return mod.part(**params)
    before = set(sys.modules)
    try:
        return mod.part(**params)
    finally:
        entry.called = True
        _note_helpers(entry, _helpers(mod, before))


#: :func:`_deferred_part`'s answer when ``part()`` is to be called again as written
_AGAIN = object()


def _deferred_part(p: Path, mod: ModuleType, params: dict[str, Any]) -> Any:
    """``mod.part(**params)`` with :func:`hnc_cam.cad.sketch.revolve` deferred
    (:func:`hnc_cam.cad.sketch.deferred`): a part that returns ``revolve(outline)`` as it is
    gives a :class:`~hnc_cam.cad.sketch.Revolved` whose profile is its outline's, and the
    CAD kernel makes no solid (nor is it imported, when the part file does not import it).
    A part that uses the solid gets it made by the first use, as ``revolve`` makes it. When
    ``part()`` fails other than by refusing its parameters (a Revolved handed to a function
    of the kernel that takes only its own objects, or any other failure), the answer is
    :data:`_AGAIN`: ``part()`` is called again without deferring, and what it does then
    (its solid, its error) is the part's."""
    try:
        with deferred():
            return _call_part(p, mod, params)
    except HncError:
        raise
    except Exception:  # noqa: BLE001 - called again as written: its error is the part's
        return _AGAIN


#: module-level names a plain modelling script leaves its solid under (build123d examples
#: use ``part``, CadQuery scripts ``result``)
SCRIPT_NAMES = ("part", "result")


def _script_part(mod: ModuleType, p: Path) -> None:
    """A plain script (no ``part()`` function) whose solid is a module-level ``part`` or
    ``result``: a part without parameters, ``part()`` giving that solid."""
    for name in SCRIPT_NAMES:
        obj = getattr(mod, name, None)
        if obj is None or isinstance(obj, (str, bytes, int, float, list, tuple, dict, ModuleType)):
            continue
        mod.part = _no_parameters(obj)
        return
    raise PartError(f"{p}: defines no function part(**params), and no solid named "
                    f"{' or '.join(SCRIPT_NAMES)}")


def _no_parameters(obj: Any):
    def part():
        return obj
    return part


def family_parameters(mod: ModuleType) -> dict[str, Any]:
    """The family's parameters: ``part``'s keyword arguments with their defaults."""
    sig = inspect.signature(mod.part)
    return {n: p.default for n, p in sig.parameters.items()
            if p.default is not inspect.Parameter.empty
            and p.kind in (p.POSITIONAL_OR_KEYWORD, p.KEYWORD_ONLY)}


def kwargs_hint(mod: ModuleType) -> str:
    """A hint for a family whose ``part`` takes ``**kwargs``: such arguments are no
    parameters (only keyword arguments with defaults are), whatever ``part`` forwards them
    to; empty when ``part`` takes none."""
    part = getattr(mod, "part", None)
    try:
        sig = inspect.signature(part) if callable(part) else None
    except (TypeError, ValueError):
        return ""
    if sig is None or not any(p.kind is p.VAR_KEYWORD for p in sig.parameters.values()):
        return ""
    return (" (the family's parameters are part()'s keyword arguments with defaults; its "
            "**kwargs declares none: write them out, e.g. def part(d1=12.0, l1=20.0))")


def _number(name: str, value: Any, default: Any, where: str) -> Any:
    if isinstance(value, bool):
        raise PartError(f"{where}: parameter {name}={value!r} is not a number")
    if isinstance(value, (int, float)):
        v = value
    else:
        s = str(value).strip()
        try:
            v = float(s)
        except ValueError:
            raise PartError(f"{where}: parameter {name}={s!r} is not a number") from None
    if not math.isfinite(v):
        raise PartError(f"{where}: parameter {name}={value!r} is not a finite number")
    if isinstance(default, int) and not isinstance(default, bool):
        if float(v) != int(v):
            raise PartError(f"{where}: parameter {name}={value!r} must be a whole number")
        return int(v)
    return float(v)


def resolve_params(mod: ModuleType, params: dict[str, Any] | None, where: str) -> dict[str, Any]:
    known = family_parameters(mod)
    params = dict(params or {})
    unknown = [k for k in params if k not in known]
    if unknown:
        raise PartError(f"{where}: unknown parameter{'s' if len(unknown) > 1 else ''} "
                        f"{', '.join(unknown)}; known: {', '.join(known) or '(none)'}"
                        + kwargs_hint(mod))
    out = dict(known)
    for k, v in params.items():
        out[k] = _number(k, v, known[k], where)
    return out


def _stock(mod: ModuleType, params: dict[str, Any], where: str) -> str | None:
    st = getattr(mod, "STOCK", None)
    if st is None:
        return None
    if callable(st):
        try:
            st = st(**params)
        except Exception as e:  # noqa: BLE001
            raise PartError(f"{where}: STOCK({_fmt(params)}) raised {type(e).__name__}: {e}") from e
    if not isinstance(st, str):
        raise PartError(f"{where}: STOCK must be a string in the stock notation, got {st!r}")
    from ..tooling import Stock
    try:
        Stock.parse(st)
    except StockError as e:
        raise PartError(f"{where}: STOCK: {e}") from None
    return st


def _threads(mod: ModuleType, params: dict[str, Any], where: str) -> list[Thread]:
    th = getattr(mod, "THREADS", None)
    if th is None:
        return []
    if callable(th):
        try:
            th = th(**params)
        except Exception as e:  # noqa: BLE001
            raise PartError(f"{where}: THREADS({_fmt(params)}) raised {type(e).__name__}: {e}") from e
    th = list(th or [])
    for t in th:
        if not isinstance(t, Thread):
            raise PartError(f"{where}: THREADS must hold hnc_cam.geometry.Thread, got {t!r}")
        _check_fields(t, where)
    return th


def _check_fields(t: Thread, where: str) -> None:
    """A thread's own numbers (PartError naming the thread): before it is placed on a part."""
    bad = [msg for ok, msg in (
        (t.pitch > 0 and math.isfinite(t.pitch), f"pitch={t.pitch!r} must be positive"),
        (t.diameter > 0 and math.isfinite(t.diameter),
         f"diameter={t.diameter!r} must be positive"),
        (isinstance(t.starts, (int, float)) and not isinstance(t.starts, bool)
         and float(t.starts).is_integer() and t.starts >= 1,
         f"starts={t.starts!r} must be a whole number >= 1"),
        (t.z_start > t.z_end, f"z_start={t.z_start!r} must be greater than z_end="
                              f"{t.z_end!r} (z_start is the end nearer the right face)"),
        (0 < t.angle < 180, f"angle={t.angle!r} must be between 0 and 180 deg"),
        (isinstance(t.taper, (int, float)) and math.isfinite(t.taper) and abs(t.taper) <= 0.25,
         f"taper={t.taper!r} must be a diameter change per mm between -0.25 and 0.25 "
         f"(1:16 = 0.0625)"),
        (not (t.internal and t.taper), "an internal taper thread is not supported (only "
                                       "external taper threads)"),
    ) if not ok]
    if bad:
        raise PartError(f"{where}: THREADS: {t}: {'; '.join(bad)}")


def _fmt(params: dict[str, Any]) -> str:
    return ", ".join(f"{k}={v:g}" if isinstance(v, (int, float)) else f"{k}={v!r}"
                     for k, v in params.items())


def load_part(path: str | Path, params: dict[str, Any] | None = None,
              **profile_kwargs: Any) -> LoadedPart:
    """Load a part file (or a STEP/BREP file) and profile it.

    ``params``: ``{"NAME": "VALUE"}`` (strings as from ``--set``, or numbers).
    ``profile_kwargs`` go to :func:`hnc_cam.cad.profile` (``axis``, ``zero``, ``envelope``,
    ``fit_tol``). Raises :class:`PartError` for the file and its parameters and
    :class:`ProfileError` when the solid cannot be profiled.
    """
    p = Path(path)
    name = profile_kwargs.pop("name", None) or p.stem
    given = list(profile_kwargs.pop("threads", None) or [])  # --thread
    if p.suffix.lower() in CAD_SUFFIXES:
        if params:
            raise PartError(f"{p}: a CAD file has no parameters (got {', '.join(params)})")
        if not p.exists():
            raise PartError(f"{p}: no such file")
        _regular(p)
        cache = ProfileCache.from_environment()
        key = cache.key(p, name, profile_kwargs) if cache is not None else None
        prof = cache.get(key) if cache is not None and key is not None else None
        if prof is None:
            from .extract import profile
            try:
                prof = profile(p, name=name, **profile_kwargs)
            except ProfileError as e:
                raise ProfileError(_cli_hints(str(e))) from None
            # cached only when the file did not change while it was read
            if cache is not None and key is not None and cache.key(p, name, profile_kwargs) == key:
                cache.put(key, prof)
        threads = _declared(prof, given, str(p))
        if threads:
            prof = dataclasses.replace(prof, threads=threads)
        return LoadedPart(profile=prof, stock=None, threads=threads, name=name, params={},
                          module=None, path=p)
    from .extract import profile
    mod = load_module(p)
    where = str(p)
    full = resolve_params(mod, params, where)
    try:
        solid = _deferred_part(p, mod, full)
        if solid is _AGAIN:
            solid = _call_part(p, mod, full)
    except PartError as e:  # the family refused the parameter set (names the parameters)
        raise PartError(f"{where}: part({_fmt(full)}): impossible part: {e}") from None
    except HncError:
        raise
    except Exception as e:  # noqa: BLE001 - the user's geometry failed: say which and with what
        raise PartError(f"{where}: part({_fmt(full)}) raised {type(e).__name__}: {e}") from e
    if solid is None:
        raise PartError(f"{where}: part({_fmt(full)}) returned None instead of a solid")
    if type(solid) is not Revolved and \
            isinstance(solid, (str, bytes, Path, int, float, list, tuple, dict)):
        raise PartError(f"{where}: part({_fmt(full)}) returned a {type(solid).__name__} "
                        f"({str(solid)[:40]!r}), not a solid (build123d, CadQuery or OCP)")
    stock = _stock(mod, full, where)
    threads = _threads(mod, full, where)
    try:
        prof = profile(solid, name=name, **profile_kwargs)
    except ProfileError as e:
        at = f"{where} ({_fmt(full)})" if full else where
        raise ProfileError(f"{at}: {_cli_hints(str(e))}") from None
    prof.params = dict(full)
    threads = _declared(prof, threads + given, where)
    prof.threads = list(threads)
    return LoadedPart(profile=prof, stock=stock, threads=threads, name=name, params=full,
                      module=mod, path=p)


#: environment variable naming the folder of the profile cache (unset: no cache)
CACHE_ENV = "HNC_CAM_PROFILE_CACHE"
_CODE_KEY: list[bytes] = []


def _code_key() -> bytes:
    """What else decides a profile besides the file: the source of the profile extractor and
    of the geometry kernel, and the OpenCascade binding's version (read from its metadata,
    without importing it)."""
    if not _CODE_KEY:
        import hashlib
        from importlib import metadata
        h = hashlib.sha256()
        root = Path(__file__).resolve().parents[1]
        for f in sorted((root / "cad").glob("*.py")) + sorted((root / "geometry").glob("*.py")) \
                + [root / "errors.py"]:
            h.update(f"{f.parent.name}/{f.name}".encode() + b"\0" + f.read_bytes() + b"\0")
        for dist in ("cadquery-ocp", "cadquery-ocp-novtk", "cadquery-ocp-proxy", "OCP"):
            try:
                h.update(f"{dist}={metadata.version(dist)}\0".encode())
            except metadata.PackageNotFoundError:
                h.update(f"{dist}=-\0".encode())
        h.update(f"{sys.version_info[:2]}".encode())
        _CODE_KEY.append(h.digest())
    return _CODE_KEY[0]


class ProfileCache:
    """Profiles of STEP/BREP files kept on disk, so that a repeated ``generate``/``verify`` of
    an unchanged file does not import or run the CAD kernel.

    The key is a SHA-256 over the file's whole contents, its resolved path and name, the
    profile options, and :func:`_code_key` (extractor and geometry source, OCP version): a
    changed byte in any of them is another key, so a stale profile is never served. An entry
    that cannot be read back as a profile (truncated, foreign, another Python) is ignored and
    rewritten; a folder that cannot be written only means no caching. Python part files are
    not cached: what they build may depend on more than their own text (modules they import,
    files they read). Enabled by ``HNC_CAM_PROFILE_CACHE=DIR``.
    """

    MAX_ENTRY = 64 * 1024 * 1024

    def __init__(self, folder: str | Path):
        self.folder = Path(folder)

    @classmethod
    def from_environment(cls) -> "ProfileCache | None":
        import os
        d = os.environ.get(CACHE_ENV, "")
        return cls(d) if d else None

    def key(self, path: Path, name: str, options: dict[str, Any]) -> str | None:
        import hashlib
        try:
            with path.open("rb") as fh:
                digest = hashlib.file_digest(fh, "sha256").digest()
        except OSError:
            return None  # the extractor reports the file's fault
        h = hashlib.sha256(b"hnc_cam profile 1\0")
        h.update(_code_key())
        h.update(str(path.resolve()).encode("utf-8", "surrogateescape") + b"\0")
        h.update(name.encode("utf-8", "surrogateescape") + b"\0")
        h.update(repr(sorted((k, repr(v)) for k, v in options.items())).encode() + b"\0")
        h.update(digest)
        return h.hexdigest()

    def get(self, key: str) -> TurnedProfile | None:
        import pickle
        f = self.folder / f"{key}.profile"
        try:
            if f.stat().st_size > self.MAX_ENTRY:
                return None
            obj = pickle.loads(f.read_bytes())
        except Exception:  # noqa: BLE001 - a missing or unreadable entry is a miss
            return None
        if not (isinstance(obj, tuple) and len(obj) == 2 and obj[0] == key
                and isinstance(obj[1], TurnedProfile)):
            return None
        return obj[1]

    def put(self, key: str, prof: TurnedProfile) -> None:
        import pickle

        from ..errors import HncError
        from ..io import write_atomic
        try:
            write_atomic(self.folder / f"{key}.profile",
                         pickle.dumps((key, prof), protocol=pickle.HIGHEST_PROTOCOL))
        except (HncError, pickle.PicklingError, RecursionError):
            pass  # no caching there; the profile itself is fine


def _regular(p: Path) -> None:
    """A part or CAD file must be a regular file (a FIFO would block the reader)."""
    import stat
    try:
        mode = p.stat().st_mode
    except OSError as e:
        raise PartError(f"{p}: cannot read: {e.strerror or e}") from None
    if stat.S_ISDIR(mode):
        raise PartError(f"{p}: is a directory, not a part file")
    if not stat.S_ISREG(mode):
        raise PartError(f"{p}: not a regular file")


def _cli_hints(msg: str) -> str:
    """A profile hint names the Python option; add the command-line one beside it."""
    msg = msg.replace("use envelope=True", "use --envelope (envelope=True)")
    msg = re.sub(r'axis="(-?[XYZ])" or "(-[XYZ])"\?', r'--axis \1 or --axis=\2 (axis="\1")?',
                 msg)
    msg = re.sub(r"axis=\(\(([^)]*)\), \(([^)]*)\)\)\?",
                 lambda m: f'--axis "{m.group(1)}, {m.group(2)}" '
                           f'(axis=(({m.group(1)}), ({m.group(2)})))?', msg)
    return msg


def profile_options(args: Any) -> dict[str, Any]:
    """``--axis``, ``--zero``, ``--envelope`` and ``--fit-tol`` of a command as keyword
    arguments of :func:`hnc_cam.cad.profile` (only those given). ``--axis``: X, Y, Z, -X, -Y,
    -Z or six numbers ``px,py,pz,dx,dy,dz`` (a point on the axis and its direction);
    ``--zero``: right, left or a coordinate along the axis."""
    out: dict[str, Any] = {}
    axis = getattr(args, "axis", None)
    if axis is not None:
        a = axis.strip().upper()
        if re.fullmatch(r"[+-]?[XYZ]", a):
            out["axis"] = a.lstrip("+")
        else:
            try:
                v = [float(t) for t in re.split(r"[,\s]+", axis.strip()) if t]
            except ValueError:
                v = []
            if len(v) != 6 or not all(math.isfinite(x) for x in v) or not any(v[3:]):
                raise PartError(f"--axis {axis!r}: expected X, Y, Z, -X, -Y, -Z or six numbers "
                                f"px,py,pz,dx,dy,dz (a point and a non-zero direction)")
            out["axis"] = (tuple(v[:3]), tuple(v[3:]))
    zero = getattr(args, "zero", None)
    if zero is not None:
        z = zero.strip().lower()
        if z in ("right", "left"):
            out["zero"] = z
        else:
            try:
                out["zero"] = float(z)
            except ValueError:
                out["zero"] = math.nan
            if not math.isfinite(out["zero"]):
                raise PartError(f"--zero {zero!r}: expected right, left or a coordinate in mm")
    if getattr(args, "envelope", False):
        out["envelope"] = True
    fit = getattr(args, "fit_tol", None)
    if fit is not None:
        out["fit_tol"] = fit
    specs = getattr(args, "thread", None)
    if specs:
        out["threads"] = [parse_thread(s) for s in specs]
    return out


_NUM = r"[+-]?(?:\d+\.?\d*|\.\d+)"
_THREAD_RE = re.compile(rf"M?({_NUM})[xX]({_NUM})@({_NUM})(?::|\.\.)({_NUM})((?:,[^,]*)*)")


def parse_thread(spec: str) -> Thread:
    """A thread given on the command line (``--thread``), for a STEP file, which cannot
    declare one, or in addition to a part file's ``THREADS``: ``[M]DxP@ZSTART:ZEND`` with
    options ``,starts=N`` ``,internal`` ``,angle=DEG`` ``,taper=1:16`` (or the diameter
    change per mm, ``taper=0.0625``; D is then the largest major diameter); Z in program
    coordinates (right face Z0), ``ZSTART`` the end nearer the right face.
    ``M20x1.5@0:-22``, ``M30x2@-5:-25,internal``."""
    text = spec.strip()
    m = _THREAD_RE.fullmatch(text)
    bad = (f"--thread {spec!r}: expected [M]DxP@ZSTART:ZEND[,starts=N][,internal]"
           f"[,angle=DEG][,taper=1:16], e.g. M20x1.5@0:-22")
    if m is None:
        raise PartError(bad)
    d, p, z0, z1 = (float(m.group(i)) for i in (1, 2, 3, 4))
    kw: dict[str, Any] = {}
    for opt in filter(None, (o.strip() for o in m.group(5).split(","))):
        key, _, val = opt.partition("=")
        key = key.strip().lower()
        try:
            if key == "internal" and not val:
                kw["internal"] = True
            elif key == "starts" and val:
                n = float(val)
                if not n.is_integer() or n < 1:
                    raise ValueError
                kw["starts"] = int(n)
            elif key == "angle" and val:
                kw["angle"] = float(val)
            elif key == "taper" and val:
                a, colon, b = val.partition(":")
                kw["taper"] = float(a) / float(b) if colon else float(val)
            else:
                raise ValueError
        except (ValueError, ZeroDivisionError):
            raise PartError(f"{bad} (not understood: {opt!r})") from None
    t = Thread(z_start=z0, z_end=z1, diameter=d, pitch=p, **kw)
    _check_fields(t, f"--thread {spec!r}")
    return t


def _declared(prof: TurnedProfile, threads: list[Thread], where: str) -> list[Thread]:
    """``threads`` (declared with the right face at Z0) moved onto the profile and checked
    against it (:func:`_check_threads`)."""
    shift = prof.z_max
    if abs(shift) > 1e-9:
        threads = [dataclasses.replace(t, z_start=t.z_start + shift, z_end=t.z_end + shift)
                   for t in threads]
    _check_threads(prof, threads, where)
    return list(threads)


def _thread_name(t: Thread) -> str:
    kind = "internal" if t.internal else "external"
    return f"{kind} thread D{t.diameter:g}x{t.pitch:g} Z{t.z_start:g}..Z{t.z_end:g}"


def _radii(chain, z: float) -> list[float]:
    from ..geometry.intersect import vertical_hits
    return [x for _, x in vertical_hits(chain, z)]


def _check_threads(prof: TurnedProfile, threads: list[Thread], where: str) -> None:
    """A declared thread must sit on the part as the solid models it (see the module
    docstring): on the part's Z span; an external thread on the outside, whose largest radius
    over the thread is between the minor and the major radius (+0.01 mm); an internal thread
    in the bore over its whole length, the bore's smallest radius over the thread between
    minor/2 - depth and major/2 (the solid models the bore at about the minor diameter).
    The outside/bore are read at 17 points of the thread's length (its ends excluded)."""
    for t in threads:
        name = _thread_name(t)
        if t.z_start > prof.z_max + 1e-6 or t.z_end < prof.z_min - 1e-6:
            raise PartError(f"{where}: {name} lies outside the part "
                            f"(Z{prof.z_max:g}..Z{prof.z_min:g})")
        zs = [t.z_start + (t.z_end - t.z_start) * (i + 0.5) / 17 for i in range(17)]
        major = t.diameter / 2
        if not t.internal and t.taper:
            # a taper thread: the part under the taper line at every point, above its root
            for z in zs:
                r = max(_radii(prof.outside, z), default=0.0)
                d = t.major_at(z)
                if r > d / 2 + 0.01:
                    raise PartError(f"{where}: {name}: the part is {2 * r:.3f} in diameter at "
                                    f"Z{z:.3f}, larger than the taper thread's major diameter "
                                    f"{d:.3f} there")
                if r < d / 2 - t.depth:
                    raise PartError(f"{where}: {name}: the part is only {2 * r:.3f} in diameter "
                                    f"at Z{z:.3f}, under the taper thread's minor diameter "
                                    f"{d - 2 * t.depth:.3f} there: nothing to thread")
            continue
        if not t.internal:
            rmax = max(max(_radii(prof.outside, z), default=0.0) for z in zs)
            if rmax > major + 0.01:
                raise PartError(f"{where}: {name}: the part is {2 * rmax:.3f} in diameter on the "
                                f"thread, larger than the major diameter {t.diameter:g} (the "
                                f"solid models the thread's major diameter)")
            if rmax < t.minor_diameter / 2:
                raise PartError(f"{where}: {name}: the part is only {2 * rmax:.3f} in diameter "
                                f"there, under the minor diameter {t.minor_diameter:.3f}: "
                                f"nothing to thread")
            continue
        if not prof.bore:
            raise PartError(f"{where}: {name} lies outside the bore: the part has no bore "
                            f"opening on the right face")
        rb: list[float] = []
        for z in zs:
            hits = _radii(prof.bore, z)
            if not hits:
                raise PartError(f"{where}: {name} lies outside the bore: no bore at Z{z:.3f} "
                                f"(the bore spans Z{prof.z_max:g}.."
                                f"Z{min(min(sg.start[1], sg.end[1]) for sg in prof.bore):g})")
            rb.append(min(hits))
        rmin = min(rb)
        if rmin >= major - 1e-9:
            raise PartError(f"{where}: {name}: the bore is {2 * rmin:.3f} in diameter there, not "
                            f"under the major diameter {t.diameter:g}: nothing to thread (the "
                            f"solid models an internal thread's minor diameter)")
        if rmin < t.minor_diameter / 2 - t.depth:
            raise PartError(f"{where}: {name}: the bore is only {2 * rmin:.3f} in diameter "
                            f"there, far under the minor diameter {t.minor_diameter:.3f} (the "
                            f"solid models an internal thread's minor diameter)")
