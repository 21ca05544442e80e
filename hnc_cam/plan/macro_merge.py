"""Decisions at the control: one macro program over variants whose programs differ in places.

The planner decides some things per variant from thresholds on the part's dimensions: a
roughing cycle split where constant surface speed meets the spindle limit (an extra inner
cycle below a diameter), the insert that roughs an undercut zone (the 55 deg one where the
zone's walls let it in), the number of passes of a chamfer at the left end. Such a decision
changes a few operations of the program, not the whole of it.

*Sections*: a program is cut at its comment lines (each operation and each tool change
starts with one) into sections; a section's key is its blocks' skeleton. Each variant's
sections are aligned with the nominal's (:class:`difflib.SequenceMatcher` on the keys); the
places where any variant differs, widened to whole sections and merged where they overlap,
are the *regions* with more than one *alternative* (the runs of sections the variants have
there). Every other section is a region of one alternative.

*Decisions*: the alternatives of a region are told apart by a binary tree of thresholds on
traced features (a parameter, a contour point's X on diameter or Z, an arc's radius): each
node's feature and cut are those that leave no alternative on both sides over the sampled
variants, the cut refined by bisection between the two nearest variants across it (to 1/4096
of their distance) and rounded to the roundest number inside the last interval. The macro
writes the tree as ``IF [cond] ... ELSE ... ENDIF`` (FANUC: ``IF [cond] GOTO n``), each branch
an alternative's sections with its own fitted words.
"""
from __future__ import annotations

from dataclasses import dataclass, field
from difflib import SequenceMatcher
from typing import Any

from .macro import _ev, _holds, _num, _params_of, features

#: bisection steps of a decision's threshold (to 1/4096 of the two sets' distance)
BISECT = 12


@dataclass
class Section:
    a: int  # first line (0-based index into the program's lines)
    b: int  # end line (exclusive)
    blocks: list  # the core blocks (macro_program.Block) in it
    key: tuple


def sections(text: str, dialect: str) -> list[Section]:
    """The program's sections after its header line (``%nnnn`` / ``Onnnn``), each starting at
    a comment-only line."""
    from .macro_program import blocks, core
    lines = text.splitlines()
    head = "O" if dialect == "fanuc0it" else "%"
    # a comment line starts a section; the 802: a ; comment or a subprogram's header
    comment = (";", "%") if dialect == "siemens802" else ("(",)
    start = next(i for i, ln in enumerate(lines) if ln.startswith(head)) + 1
    allb = blocks(text)
    at = {b.line for b in allb}
    cb = {b.line: b for b in core(allb)}
    cuts = [start]
    for i in range(start, len(lines)):
        s = lines[i].strip()
        if s.startswith(comment) and (i + 1) not in at and \
                any(ln in cb for ln in range(cuts[-1] + 1, i + 1)):
            cuts.append(i)
    cuts.append(len(lines))
    out = []
    for a, b in zip(cuts, cuts[1:]):
        bs = [cb[ln] for ln in range(a + 1, b + 1) if ln in cb]
        out.append(Section(a, b, bs, tuple(x.key for x in bs)))
    return out


@dataclass
class Prog:
    """One variant's program cut into sections, aligned with the nominal's."""
    p: dict[str, Any]
    text: str
    secs: list[Section]
    ops: list[tuple] = field(default_factory=list)

    @property
    def keys(self) -> list[tuple]:
        return [s.key for s in self.secs]


def prog(p: dict[str, Any], text: str, dialect: str) -> Prog:
    return Prog(p, text, sections(text, dialect))


def align(nom: Prog, v: Prog) -> None:
    v.ops = SequenceMatcher(None, nom.keys, v.keys, autojunk=False).get_opcodes()


def hunks(nom: Prog, progs: list[Prog], also: list[int] = ()) -> list[tuple[int, int]]:
    """The nominal's section ranges [a, b) where some variant differs (and the sections
    ``also``: where a word switches between two laws), merged where they overlap (an
    insertion takes the section after it, or the last one)."""
    n = len(nom.secs)
    ivs = [(j, j + 1) for j in also]
    for v in progs:
        for tag, i1, i2, _j1, _j2 in v.ops:
            if tag == "equal":
                continue
            if i2 > i1:
                ivs.append((i1, i2))
            else:
                ivs.append((i1, i1 + 1) if i1 < n else (i1 - 1, i1))
    links = cycle_links(nom)
    while True:
        ivs.sort()
        out: list[list[int]] = []
        for a, b in ivs:
            if out and a < out[-1][1]:
                out[-1][1] = max(out[-1][1], b)
            else:
                out.append([a, b])
        # a cycle and the contour it names are decided together
        more = [(a, b) for a, b in links
                if any(a < y and x < b for x, y in out) and
                not any(x <= a and b <= y for x, y in out)]
        if not more:
            return [(a, b) for a, b in out]
        ivs = [tuple(x) for x in out] + more


def cycle_links(nom: Prog) -> list[tuple[int, int]]:
    """The section ranges from each roughing cycle to the blocks its P/Q name."""
    import re
    where_n: dict[str, int] = {}
    for j, sec in enumerate(nom.secs):
        for b in sec.blocks:
            m = re.match(r"\s*N(\d+)", b.raw)
            if m:
                where_n[m.group(1)] = j
    out = []
    for j, sec in enumerate(nom.secs):
        for b in sec.blocks:
            if any(w.letter == "G" and float(w.text) in (70, 71, 72, 73) for w in b.words):
                for w in b.words:
                    if w.letter in "PQ" and w.text in where_n:
                        k = where_n[w.text]
                        out.append((min(j, k), max(j, k) + 1))
    return out


def regions(nom: Prog, progs: list[Prog], also: list[int] = ()) -> list[tuple[int, int]]:
    """Every section of the nominal in a region: the hunks, and each other section alone."""
    hs = hunks(nom, progs, also)
    out, i = [], 0
    for a, b in hs:
        out += [(k, k + 1) for k in range(i, a)]
        out.append((a, b))
        i = b
    out += [(k, k + 1) for k in range(i, len(nom.secs))]
    return out


def where(v: Prog, i: int, n: int) -> int | None:
    """The variant's section index at the nominal's boundary ``i`` (None: inside a change)."""
    if i == n:
        return len(v.secs)
    for tag, i1, i2, j1, _j2 in v.ops:
        if i1 == i:
            return j1
        if tag == "equal" and i1 < i < i2:
            return j1 + i - i1
        if i1 < i < i2:
            return None
    return None


def alt_key(nom: Prog, v: Prog, reg: tuple[int, int]) -> tuple | None:
    n = len(nom.secs)
    a, b = where(v, reg[0], n), where(v, reg[1], n)
    if a is None or b is None or b < a:
        return None
    return tuple(v.keys[a:b])


def run_of(nom: Prog, v: Prog, reg: tuple[int, int]) -> list[Section]:
    n = len(nom.secs)
    return v.secs[where(v, reg[0], n):where(v, reg[1], n)]


# ------------------------------------------------------------------------------------------
# decision trees
# ------------------------------------------------------------------------------------------

@dataclass
class Node:
    """A decision: ``cond`` true -> ``yes``, else ``no``; a leaf holds an alternative's index."""
    leaf: int | None = None
    cond: tuple | None = None
    label: str = ""
    yes: "Node | None" = None
    no: "Node | None" = None

    def pick(self, p: dict[str, Any]) -> int:
        node = self
        while node.leaf is None:
            node = node.yes if _holds(node.cond, p) else node.no
        return node.leaf

    def paths(self, acc: tuple = ()) -> dict[int, list[tuple]]:
        """Each leaf's conditions from the root."""
        if self.leaf is not None:
            return {self.leaf: list(acc)}
        out = self.yes.paths(acc + (self.cond,))
        out.update(self.no.paths(acc + (("not", self.cond),)))
        return out

    def labels(self) -> list[str]:
        if self.leaf is not None:
            return []
        return [self.label] + self.yes.labels() + self.no.labels()


def _roundest(a: float, b: float) -> float:
    """The number with the fewest decimals in [a, b]."""
    lo, hi = min(a, b), max(a, b)
    for nd in range(9):
        for r in (round(lo, nd), round(hi, nd), round((lo + hi) / 2, nd)):
            if lo <= r <= hi:
                return r
    return (lo + hi) / 2


def slopes(tr: Any) -> list[tuple[str, tuple]]:
    """Each traced line's slope (radial over axial change): where an insert reaches a wall
    follows the wall's angle, a ratio of its ends' coordinates."""
    from .macro import _node
    out = []
    for i, sg in enumerate(tr.segments):
        if sg[0] != "L":
            continue
        x0, z0, x1, z1 = (_node(sg[1][0]), _node(sg[1][1]), _node(sg[2][0]), _node(sg[2][1]))
        out.append((f"segment {i + 1} slope", ("/", ("-", x1, x0), ("-", z1, z0))))
    return out


#: the best-scored cuts a node tries, each refined by bisection, until one holds
TRIES = 4


def _refine(fam: Any, f: tuple, p0: dict, p1: dict, test: Any, right: set,
            side: Any) -> tuple[float, float] | None:
    """The feature ``f`` just before and after the label changes between ``p0`` (its label
    passes ``test``) and ``p1``: bisected along the way that moves only the parameters of
    ``f`` (from ``p0``, else toward ``p1``), so that no other decision's boundary is crossed
    on the way, else along the straight way. A way that meets a sampled alternative of
    neither side (another decision's boundary) or where ``f`` does not move says nothing: None
    when no way holds. Also the set just before the change."""
    own = _params_of(f) & set(fam.free)
    ways = []
    if own and own != set(fam.free):
        ways += [(p0, dict(p0, **{k: p1[k] for k in own})),
                 (dict(p1, **{k: p0[k] for k in own}), p1)]
    ways.append((p0, p1))
    for q0, q1 in ways:
        def at(t: float, q0=q0, q1=q1) -> dict:
            return {k: (q0[k] + t * (q1[k] - q0[k]) if k in fam.free else q0[k]) for k in q0}

        def label(t: float, q0=q0, q1=q1, at=at) -> Any:
            lab = side(q0, q1, t)
            if lab is None:  # no program there: the set a control holds (0.001) beside it
                near = {k: (round(v, 3) if k in fam.free else v) for k, v in at(t).items()}
                lab = side(near, near, 0.0)
            return lab

        def on(lab: Any) -> int | None:  # 0 left, 1 right, None: an alternative of neither
            if lab is None:  # no program, or one no sampled set has: counted with the right
                return 1
            return _on_side(lab, test, right)
        if q0 is not p0 and on(label(0.0)) != 0:
            continue
        if q1 is not p1 and on(label(1.0)) != 1:
            continue
        a, b = 0.0, 1.0
        for _ in range(BISECT):
            m = (a + b) / 2
            s = on(label(m))
            if s is None:
                break
            if s == 0:
                a = m
            else:
                b = m
        else:
            fa, fb = _ev(f, at(a)), _ev(f, at(b))
            if abs(fb - fa) > 1e-12:
                return fa, fb, at(a)
    return None


def _straight(fam: Any, f: tuple, p0: dict, p1: dict, test: Any,
              side: Any) -> tuple[float, float, dict]:
    """The feature ``f`` before and after the label changes along the straight way from
    ``p0`` to ``p1``, anything not passing ``test`` counted with ``p1``'s side."""
    a, b = 0.0, 1.0
    for _ in range(BISECT):
        m = (a + b) / 2
        lab = side(p0, p1, m)
        if lab is not None and test(lab):
            a = m
        else:
            b = m

    def at(t: float) -> dict:
        return {k: (p0[k] + t * (p1[k] - p0[k]) if k in fam.free else p0[k]) for k in p0}
    return _ev(f, at(a)), _ev(f, at(b)), at(a)


def _at_tie(fam: Any, f: tuple, c: float, op: str, fa: float, fb: float, qa: dict, test: Any,
            right: set, side: Any) -> tuple[float, str]:
    """The threshold ``f op c`` with the side the planner gives a set of the control's
    precision (0.001) at which ``f`` is ``c`` itself: the set just left of the change
    (``qa``) rounded, one of ``f``'s parameters moved to where ``f`` is ``c``. A round
    threshold is often the planner's own (a groove from length 52, a split at the written
    diameter 21.496), and a table row there is a natural one. A parameter compares exactly
    (``<=`` or ``<``); a feature computed from several is moved half of its finest step at
    that precision toward the side that does not take the tie, so that the control's
    rounding of the expression does not decide it. Unchanged where no such set is in the
    domain, or it makes no program."""
    import math
    base = {k: (round(v, 3) if k in fam.free else v) for k, v in qa.items()}
    try:
        f0 = _ev(f, base)
    except (ValueError, ZeroDivisionError, OverflowError):
        return c, op
    steps, tie = [], None
    for k in sorted(_params_of(f) & set(fam.free)):
        q = dict(base, **{k: base[k] + 0.001})
        try:
            a = (_ev(f, q) - f0) / 0.001
        except (ValueError, ZeroDivisionError, OverflowError):
            continue
        if not math.isfinite(a) or abs(a) < 1e-9:
            continue
        steps.append(abs(a) * 0.001)
        if tie is not None:
            continue
        q[k] = round(base[k] + (c - f0) / a, 3)
        if not fam.lo.get(k, -math.inf) <= q[k] <= fam.hi.get(k, math.inf):
            continue
        try:
            if abs(_ev(f, q) - c) > 1e-9:
                continue
        except (ValueError, ZeroDivisionError, OverflowError):
            continue
        tie = q
    if tie is None:
        return c, op
    lab = side(tie, tie, 0.0)
    at = None if lab is None else _on_side(lab, test, right)
    if at is None:
        return c, op  # no program there, or an alternative of neither side
    left = at == 0
    rising = fa < fb  # the left side below the threshold
    if f[0] == "p":
        return c, ("<=" if left else "<") if rising else (">=" if left else ">")
    h = min(steps) / 2
    if rising:
        return (c + h if left else c - h), "<"
    return (c - h if left else c + h), ">"


#: the sets beside a refined threshold (within EDGE of its feature's span over the variants)
#: on which its feature must tell the alternatives apart before the cut is taken
N_EDGE, EDGE = 6, 0.05


def _edge_holds(f: tuple, c: float, op: str, width: float, path: list[tuple], test: Any,
                right: set, side: Any, probe: Any) -> bool:
    """Whether the sets ``probe`` draws beside the threshold ``f op c`` (inside the node's
    own part of the domain, ``path``) fall on the side it puts them: a feature that separates
    the sampled variants and whose bisection holds on one way may still not be the planner's
    (the end of a chamfered edge where the planner tests the diameter), which sets beside
    the cut with the other parameters elsewhere show."""
    near = [(">=", f, ("c", c - width)), ("<=", f, ("c", c + width))]
    memo = getattr(probe, "memo", None)  # a cut proven in an earlier round stays proven
    key = repr((f, round(c, 4), op, tuple(path)))
    if memo is not None and key in memo:
        return memo[key]
    ok = _edge_sets_hold(f, c, op, probe(list(path) + near, N_EDGE), test, right, side)
    if memo is not None:
        memo[key] = ok
        if ok:
            memo.setdefault(PROVEN, []).append((repr(tuple(path)), f, c, op))
    return ok


#: the memo's entry of the cuts proven (their node's path, feature, threshold, comparison)
PROVEN = "proven"


def _proven_cut(memo: dict | None, path: tuple, idx: list[int], sets: list[dict],
                labels: list[int]) -> tuple | None:
    """A cut proven at this node (``path``) in an earlier round that still parts the node's
    sampled sets ``idx`` into alternatives of disjoint sides: (feature, threshold, comparison,
    left, right). More variants move the best-scored candidates; a cut bisected and proven
    beside its threshold stays the planner's, where a candidate scored first on the new sets
    may only pass its own proof by chance."""
    if not memo:
        return None
    at = repr(tuple(path))
    for where_, f, c, op in memo.get(PROVEN, ()):
        if where_ != at:
            continue
        try:
            left = [i for i in idx if _holds((op, f, ("c", c)), sets[i])]
        except (ValueError, ZeroDivisionError, OverflowError):
            continue
        lset = set(left)
        right = [i for i in idx if i not in lset]
        if left and right and not {labels[i] for i in left} & {labels[i] for i in right}:
            return f, c, op, left, right
    return None


def _on_side(lab: Any, test: Any, right: set) -> int | None:
    """The side of a cut a label (not None) is on: 0 left (it passes ``test``), 1 right (one
    of ``right``, or any where ``right`` is empty), None an alternative of neither side."""
    return 0 if test(lab) else 1 if lab in right or not right else None


def _edge_sets_hold(f: tuple, c: float, op: str, sets: list[dict], test: Any, right: set,
                    side: Any) -> bool:
    for q in sets:
        lab = side(q, q, 0.0)
        if lab is None:
            continue
        on = _on_side(lab, test, right)
        if on is not None and (on == 0) != _holds((op, f, ("c", c)), q):
            return False
    return True


def build_tree(fam: Any, tr: Any, sets: list[dict], labels: list[int], side: Any,
               strict: bool = True, probe: Any = None) -> Node | None:
    """The decision tree telling the labels apart by thresholds on one traced feature per
    node, or None. ``side(p0, p1, t)`` -> the label at the set ``t`` of the way from ``p0`` to
    ``p1`` (for bisection; None where it is another change). ``strict``: each threshold
    bisected along its feature's own parameters (:func:`_refine`); where no such tree holds,
    the tree of the best cuts bisected along the straight ways. ``probe(conds, n)``: up to
    ``n`` sets of the domain that meet ``conds``, on which a refined cut is proven
    (:func:`_edge_holds`) before it is taken."""
    most = 2 * len(set(labels)) - 1
    for st in ((True, False) if strict else (False,)):
        tree = _build(fam, tr, sets, labels, side, st, probe)
        # a tree of more thresholds than two per alternative follows the sampled sets, not
        # a rule of the planner's that these features hold (its test combines several
        # dimensions): none
        if tree is not None and len(tree.labels()) <= most:
            return tree
    return None


def _build(fam: Any, tr: Any, sets: list[dict], labels: list[int], side: Any,
           strict: bool, probe: Any = None) -> Node | None:
    import numpy as np
    cands = [(k, ("p", k)) for k in fam.free] + features(tr) + slopes(tr)
    cols = []
    for desc, f in cands:
        try:
            v = np.array([_ev(f, p) for p in sets])
        except (ValueError, ZeroDivisionError, OverflowError):
            continue
        if np.all(np.isfinite(v)) and np.ptp(v) > 1e-9:
            cols.append((desc if f[0] != "p" else f[1], f, v))

    def cut_of(fa: float, fb: float) -> tuple[float, str]:
        c = _roundest(fa, fb)
        # a round value the last set on the left side has itself (the planner's own
        # threshold, as ceil(depth / step) at a whole depth) stays on the left
        return c, ("<=" if c == fa else "<") if fa < fb else (">=" if c == fa else ">")

    def grow(idx: list[int], path: tuple = ()) -> Node | None:
        labs = {labels[i] for i in idx}
        if len(labs) == 1:
            return Node(leaf=labs.pop())
        kept = _proven_cut(getattr(probe, "memo", None), path, idx, sets, labels)
        if kept is not None:
            f, c, op, lidx, ridx = kept
            desc = next((d for d, g, _v in cols if g == f), None)
            if desc is not None:
                return _node(path, desc, f, c, op, lidx, ridx)
        found = []
        for desc, f, v in cols:
            order = sorted(idx, key=lambda i: v[i])
            span = np.ptp(v) or 1.0
            cuts = []  # (k, test of a label on the left side, disjoint)
            for k in range(1, len(order)):
                left = {labels[i] for i in order[:k]}
                right = {labels[i] for i in order[k:]}
                if not left & right:
                    cuts.append((k, left.__contains__, True))
            # one side a single alternative, the other side decided further down
            lab0, lab1 = labels[order[0]], labels[order[-1]]
            k0 = next((k for k in range(len(order)) if labels[order[k]] != lab0), None)
            if k0:
                cuts.append((k0, lab0.__eq__, False))
            k1 = max(k for k in range(len(order)) if labels[order[k]] != lab1) + 1
            if k1 < len(order):
                cuts.append((k1, lambda lab, r=lab1: lab is not None and lab != r, False))
            for k, test, disjoint in cuts:
                gap = v[order[k]] - v[order[k - 1]]
                if gap < 1e-9:
                    continue
                found.append(((disjoint, gap / span), desc, f, order[k - 1], order[k], test,
                              order[:k], order[k:]))
        found.sort(key=lambda c: c[0], reverse=True)
        best = None
        for cand in found[:TRIES]:  # (also where the tree is not strict: node by node)
            _score, desc, f, ia, ib, test, lidx, ridx = cand
            right = {labels[i] for i in ridx} - {labels[i] for i in lidx}
            ends = _refine(fam, f, sets[ia], sets[ib], test, right, side)
            if ends is None:
                continue
            c, op = _at_tie(fam, f, *cut_of(ends[0], ends[1]), *ends, test, right, side)
            if probe is not None:
                width = EDGE * float(np.ptp([_ev(f, sets[i]) for i in range(len(sets))]))
                if not _edge_holds(f, c, op, width, list(path), test, right, side, probe):
                    continue
            best = cand
            break
        if best is None and found and not strict:  # the best cut along the straight way
            best = found[0]
            _score, desc, f, ia, ib, test, lidx, ridx = best
            right = {labels[i] for i in ridx} - {labels[i] for i in lidx}
            ends = _straight(fam, f, sets[ia], sets[ib], test, side)
            c, op = _at_tie(fam, f, *cut_of(ends[0], ends[1]), *ends, test, right, side)
        if best is None:
            return None
        _score, desc, f, ia, ib, test, lidx, ridx = best
        return _node(path, desc, f, c, op, lidx, ridx)

    def _node(path: tuple, desc: str, f: tuple, c: float, op: str, lidx: list[int],
              ridx: list[int]) -> Node | None:
        idx = lidx + ridx
        cond = (op, f, ("c", c))
        yes, no = grow(lidx, path + (cond,)), grow(ridx, path + (("not", cond),))
        if yes is None or no is None:
            return None
        label = f"{desc} {op} {_num(c)}"
        node = Node(cond=cond, label=label, yes=yes, no=no)
        if any(node.pick(sets[i]) != labels[i] for i in idx):
            return None
        return node

    return grow(list(range(len(sets))))
