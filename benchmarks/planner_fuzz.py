"""Fuzzer of the planner, the way a user meets it: random turned parts written as part files
(the sketch helpers' ``Outline`` + ``revolve``, or plain build123d), each run through
``hnc-cam generate`` in both compensation modes and every dialect.

A part file holds steps (some near the diameter where G96 reaches the spindle limit, where
the HNC-21T's G71 runs in two), chamfers, fillets, grooves (square or round), tapers, a
convex arc, a journal stepping down toward the chuck, a right end that is a face, a cone to
a point or a ball, and sometimes a through bore with a counterbore or a blind bore; the
largest diameter 8 to 80 mm. Every run must end in a verified program (exit 0) or a
one-line refusal (exit 2, one line ``error: ...`` that is not an internal error). Anything
else (exit 1: the program failed its verification; an internal error; a traceback; more than
one line) is a failure, printed with the part file's text and the command that reproduces it.

Run: ``python benchmarks/planner_fuzz.py --parts N --seed S [--save DIR] [--seconds S]
[--comp cam,control] [--dialect hnc21t,...]``. Prints one line per run that is not a pass,
the counts (parts x modes x dialects: pass / refused / failed), the seconds taken, and exits 1
when anything failed. ``--save DIR`` keeps the part files (else a temporary folder).
"""
from __future__ import annotations

import argparse
import contextlib
import io
import math
import random
import sys
import tempfile
import time
import traceback
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
if str(ROOT) not in sys.path:
    sys.path.insert(0, str(ROOT))

DIALECTS = ("hnc21t", "fanuc0it", "haas", "siemens802")
COMPS = ("cam", "control")


def _f(v: float) -> str:
    return f"{v:.3f}".rstrip("0").rstrip(".")


def random_part(rng: random.Random, name: str) -> str:
    """The text of a part file: a random turned part as a user writes one."""
    d_max = rng.uniform(8.0, 80.0)
    r_max = round(d_max / 2, 1)
    length = round(min(150.0, max(6.0, d_max * rng.uniform(0.4, 2.5))), 1)
    bore = rng.random() < 0.3 and r_max >= 8
    if bore and rng.random() < 0.8:
        length = min(length, 60.0)  # within the bundled boring bar's reach, mostly
    rb = round(r_max * rng.uniform(0.25, 0.5), 1) if bore else 0.0
    # a counterbore on the right of a through bore: (radius, depth)
    cb = None
    if bore and rng.random() < 0.4:
        cb = (round(rb + rng.uniform(1.0, 0.4 * (r_max - rb)), 1),
              round(rng.uniform(0.1, 0.4) * length, 1))
    # a blind bore from the right face (a solid part): (radius, depth)
    blind = None
    if not bore and r_max >= 10 and rng.random() < 0.15:
        blind = (round(r_max * rng.uniform(0.25, 0.45), 1),
                 round(min(length * rng.uniform(0.2, 0.6), 60.0), 1))
    x_in = cb[0] if cb else blind[0] if blind else rb  # where the OD starts on the right face
    r_min = max(x_in + max(1.5, 0.15 * r_max), r_max * 0.35)
    # the right end of a solid part: a face, a cone to a point or a ball
    end = "face"
    if x_in == 0.0:
        end = rng.choices(["face", "cone", "ball"], [0.8, 0.12, 0.08])[0]
    # OD sections from the right face toward the chuck
    n = rng.randint(1, 4)
    radii = sorted(round(rng.uniform(r_min, r_max), 1) for _ in range(n - 1)) + [r_max]
    # steps of at least 0.6 mm (radius), mostly: a smaller one is a refusal (the nose)
    if rng.random() < 0.9:
        radii = [r for k, r in enumerate(radii) if k == len(radii) - 1 or radii[k + 1] - r >= 0.6]
    if len(radii) >= 2 and r_min < 9.0 < radii[-2] and rng.random() < 0.3:
        # a step near the diameter where G96 reaches the spindle limit (the G71 split)
        radii[-2] = round(rng.uniform(8.8, 10.0), 2)
    if n >= 2 and rng.random() < 0.1:  # a journal on the left end, smaller: a second setup
        radii.append(round(rng.uniform(r_min, r_max - 1.0), 1))
    cuts = sorted(rng.uniform(0.1, 0.9) * length for _ in range(len(radii) - 1))
    zs = [0.0] + [-round(c, 1) for c in cuts] + [-length]
    # the OD polyline: [x, z, what the element *to* this point is, its size, may the corner
    # at this point take a chamfer or fillet]
    pts: list[list] = [[x_in, 0.0, "line", 0.0, True]]
    if blind:
        pts = [[0.0, -blind[1], "line", 0.0, False], [blind[0], -blind[1], "line", 0.0, True]] \
            + pts
    for i, r in enumerate(radii):
        z_a, z_b = zs[i], zs[i + 1]
        w = z_a - z_b
        if w < 0.6:
            continue
        if i == 0 and end == "ball" and w > r + 1.0:
            pts.append([r, -r, "ball", r, True])
            pts.append([r, z_b, "line", 0.0, True])
            continue
        if (i > 0 or end == "cone") and (end == "cone" or rng.random() < 0.2) \
                and r > pts[-1][0] + 0.5:
            # a taper from the previous radius instead of a shoulder
            pts.append([r, z_a - min(w * 0.5, rng.uniform(0.5, 3) * (r - pts[-1][0])),
                        "line", 0.0, True])
        else:
            pts.append([r, z_a, "line", 0.0, True])
        zc = pts[-1][1]
        if zc - z_b > 10 and rng.random() < 0.35:  # a groove in the section
            # wider than the bundled 3 mm blade, mostly
            gw = round(rng.uniform(3.0 if rng.random() < 0.85 else 1.5,
                                   max(3.1, min(8.0, (zc - z_b) / 3))), 2)
            gd = round(rng.uniform(0.3, min(3.0, (r - x_in) * 0.4)), 2)
            gz = zc - round(rng.uniform(0.3, 0.6) * (zc - z_b), 1)
            soft = rng.random() < 0.15  # corners of the groove chamfered/filleted too
            if rng.random() < 0.3:  # a round groove: an arc into the material
                pts.append([r, gz, "line", 0.0, False])
                pts.append([r, gz - gw, "groove_arc",
                            round(max(gw / 2 + 0.01, gd * rng.uniform(1.0, 3.0)), 3), False])
            else:
                pts += [[r, gz, "line", 0.0, soft], [r - gd, gz, "line", 0.0, soft],
                        [r - gd, gz - gw, "line", 0.0, soft], [r, gz - gw, "line", 0.0, soft]]
        elif zc - z_b > 6 and r < r_max - 1.0 and rng.random() < 0.25:
            # a convex arc over the section, at most as high as the largest diameter
            h = rng.uniform(0.3, min(1.5, r_max - r))
            c = zc - z_b - 2.0
            pts.append([r, zc - 1.0, "line", 0.0, False])
            pts.append([r, z_b + 1.0, "bulge", round((c * c / 4 + h * h) / (2 * h), 3), False])
        pts.append([r, z_b, "line", 0.0, True])
    pts.append([rb, -length, "line", 0.0, False])
    if cb:
        pts += [[rb, -cb[1], "line", 0.0, True], [cb[0], -cb[1], "line", 0.0, True]]
    # equal neighbours (two radii rounded alike) are one point
    pts = [p for k, p in enumerate(pts)
           if k == 0 or math.dist(p[:2], pts[k - 1][:2]) > 1e-9 or p[2] != "line"]
    arcs = any(p[2] != "line" for p in pts)
    plain = not arcs and rng.random() < 0.3  # plain build123d: a Polyline, no corner words
    # corners where both lines beside them leave room: chamfers or fillets; the left end's
    # corner (toward the chuck) a chamfer only, and rarely
    lines = []
    for k in range(1, len(pts)):
        x, z, kind, size, soft = pts[k]
        if kind == "groove_arc":
            lines.append(f"    s.arc_to({_f(x)}, {_f(z)}, radius={_f(size)}, cw=True)")
            continue
        if kind == "ball":
            lines.append(f"    s.arc_to({_f(x)}, {_f(z)}, radius={_f(size)}, cw=False)")
            continue
        if kind == "bulge":
            lines.append(f"    s.arc_to({_f(x)}, {_f(z)}, radius={_f(size)}, cw=False)")
            continue
        opts = ""
        nxt = pts[k + 1] if k + 1 < len(pts) else (pts[0] if bore else None)
        if soft and nxt is not None and nxt[2] == "line" and pts[k - 1][2] == "line" \
                and not plain:
            room = min(math.dist(pts[k - 1][:2], pts[k][:2]), math.dist(pts[k][:2], nxt[:2]))
            left_end = abs(z + length) < 1e-9
            if room > 1.0 and rng.random() < (0.2 if left_end else 0.6):
                size = round(min(2.0, room * rng.uniform(0.1, 0.35)), 2)
                kind = "chamfer" if left_end or rng.random() < 0.6 else "fillet"
                opts = f", {kind}={_f(size)}"
        lines.append(f"    s.line_to({_f(x)}, {_f(z)}{opts})")
    stock = ""
    u = rng.random()
    if u < 0.6:
        face = rng.choice(["", "+0.5", "+1", "+2"])
        stock = (f"STOCK = \"{_f(2 * r_max + rng.choice([2, 3, 4, 6]))}"
                 + (f"/{_f(max(2.0, 2 * rb - rng.choice([2, 3, 4])))}" if bore else "")
                 + f"x{_f(length + rng.choice([3, 10, 30, 45]))}{face}\"\n\n\n")
    what = (f"largest diameter {_f(2 * r_max)}, length {_f(length)}"
            + (f", a {end} on the right" if end != "face" else "")
            + (f", blind bore {_f(2 * blind[0])} {_f(blind[1])} deep" if blind else "")
            + (f", through bore {_f(2 * rb)}" if bore else "")
            + (f", counterbore {_f(2 * cb[0])} {_f(cb[1])} deep" if cb else ""))
    if plain:
        poly = ", ".join(f"({_f(p[0])}, {_f(p[1])})" for p in pts)
        return (f'"""Random turned part {name}: {what}; plain build123d."""\n'
                "from build123d import (Axis, BuildLine, BuildPart, BuildSketch, Plane, "
                "Polyline, make_face, revolve)\n\n"
                f"{stock}"
                "def part():\n"
                "    with BuildPart() as p:\n"
                "        with BuildSketch(Plane.XZ):\n"
                "            with BuildLine():\n"
                f"                Polyline({poly}, close=True)\n"
                "            make_face()\n"
                "        revolve(axis=Axis.Z)\n"
                "    return p.part\n")
    close = "    s.close()\n" if bore else ""
    body = "\n".join(lines)
    return (f'"""Random turned part {name}: {what}."""\n'
            "from hnc_cam.cad.sketch import Outline, revolve\n\n"
            f"{stock}"
            "def part():\n"
            f"    s = Outline(({_f(pts[0][0])}, {_f(pts[0][1])}))\n"
            f"{body}\n{close}"
            "    return revolve(s.segments())\n")


def run_generate(path: Path, comp: str, dialect: str, out: Path) -> tuple[str, str]:
    """``hnc-cam generate`` in this process: (verdict, what it printed on stderr); verdict
    pass | refused | failed."""
    from hnc_cam.cli import main
    err, std = io.StringIO(), io.StringIO()
    try:
        with contextlib.redirect_stderr(err), contextlib.redirect_stdout(std):
            rc = main(["generate", str(path), "--comp", comp, "--dialect", dialect,
                       "-o", str(out)])
    except BaseException:  # noqa: BLE001 - a traceback is the failure we look for
        return "failed", "traceback: " + traceback.format_exc().strip().splitlines()[-1]
    text = err.getvalue().strip()
    lines = [ln for ln in text.splitlines() if not ln.startswith("warning: ")]
    if rc == 0:
        return "pass", ""
    if rc == 2 and len(lines) == 1 and lines[0].startswith("error: ") and \
            "internal error" not in lines[0]:
        return "refused", lines[0]
    return "failed", f"exit {rc}: " + " | ".join(lines)[:600]


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--parts", type=int, default=40)
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--save", type=Path, default=None)
    ap.add_argument("--seconds", type=float, default=0.0, help="stop starting parts after this")
    ap.add_argument("--comp", default=",".join(COMPS))
    ap.add_argument("--dialect", default=",".join(DIALECTS))
    a = ap.parse_args(argv)
    comps = [c for c in a.comp.split(",") if c]
    dialects = [d for d in a.dialect.split(",") if d]
    rng = random.Random(a.seed)
    tmp = None
    if a.save is None:
        tmp = tempfile.TemporaryDirectory(prefix="planner_fuzz_")
        folder = Path(tmp.name)
    else:
        folder = a.save
        folder.mkdir(parents=True, exist_ok=True)
    counts = {"pass": 0, "refused": 0, "failed": 0}
    failed_parts: list[str] = []
    t0 = time.perf_counter()
    done = 0
    for i in range(a.parts):
        if a.seconds and time.perf_counter() - t0 > a.seconds:
            break
        name = f"fz{a.seed}_{i:03d}"
        path = folder / f"{name}.py"
        path.write_text(random_part(rng, name), "utf-8")
        done += 1
        bad = False
        for comp in comps:
            for d in dialects:
                verdict, msg = run_generate(path, comp, d, folder / f"{name}_{comp}_{d}.nc")
                counts[verdict] += 1
                if verdict != "pass":
                    print(f"{verdict}: {path.name} --comp {comp} --dialect {d}: {msg}",
                          flush=True)
                bad |= verdict == "failed"
        if bad:
            failed_parts.append(path.read_text("utf-8"))
    dt = time.perf_counter() - t0
    for text in failed_parts:
        print("---- failing part file:\n" + text)
    print(f"{done} parts x {len(comps)} modes x {len(dialects)} dialects = "
          f"{sum(counts.values())} runs: {counts['pass']} pass, {counts['refused']} refused, "
          f"{counts['failed']} failed; {dt:.0f} s")
    if tmp is not None:
        tmp.cleanup()
    return 1 if counts["failed"] else 0


if __name__ == "__main__":
    sys.exit(main())
