"""The HNC-21T macro memory map (manual 3.4.1, appendix 1).

``#0-#49`` locals of the current level, ``#50-#199`` globals, ``#200+50*L+i`` local ``i`` of
level ``L``, ``#600+n`` / ``#700+n`` register n's Z offset / nose radius, ``#800+n`` tool
life, ``#1000+`` system variables (positions, work zeros, the G28 point, the modal codes of
table 3.2), ``#2000-#2600`` the cycle contour table. A variable never assigned is vacant
(None); reading one in an expression is an alarm. The interpreter
(:class:`hnc_cam.nc.interp.Interp`) mixes this class in; other dialects replace these
methods with their own map.
"""
from __future__ import annotations

from ...nc.expr import EvalError


class HncMemory:
    """Reads and writes of HNC-21T macro variables (methods of the interpreter)."""

    def _read(self, n, strict_vacant: bool = True):
        if n is None:
            raise EvalError("undefined variable used as a variable number")
        if isinstance(n, float) and not n.is_integer() or n != n:
            raise EvalError(f"invalid variable #{n:g}: not an integer")
        n = int(n)
        if 0 <= n < 50:
            v = self.L[n]
        elif 50 <= n < 200:
            v = self.G[n]
        elif 200 <= n < 600:
            lv, j = divmod(n - 200, 50)
            v = self.levels[lv][j]
        elif 600 <= n < 900:
            k, r = divmod(n - 600, 100)
            if k == 2:
                v = self.life.get(r, 0.0)
            else:
                reg = self._register(r)
                v = reg.z if k == 0 else reg.radius
        elif 1000 <= n < 1200:
            v = self._sysvar(n)
        elif 2000 <= n <= 2600:
            v = self.table[n - 2000]
        else:
            raise EvalError(f"undefined variable #{n}: no such variable (see manual 3.4.1)")
        if v is None and strict_vacant:
            raise EvalError(f"undefined variable #{n}: it was never assigned")
        return v

    def _sysvar(self, n: int):
        mx, mz = self.x + self.ox, self.z + self.oz
        if n == 1009:
            return 1.0 if self.diam else 0.0
        if 1000 <= n <= 1018:
            k = n - 1000 if n < 1010 else n - 1010
            return mx if k == 0 else mz if k == 2 else 0.0
        if 1020 <= n <= 1028:
            k = n - 1020
            return self.x if k == 0 else self.z if k == 2 else 0.0
        if 1030 <= n <= 1038:
            k = n - 1030
            return self.ox if k == 0 else self.oz if k == 2 else 0.0
        if 1040 <= n <= 1099:
            g, k = divmod(n - 1040, 10)
            if k == 9:
                raise EvalError(f"undefined variable #{n}: reserved")
            o = self.wcs_tab.get(54 + g, (0.0, 0.0))
            return o[0] if k == 0 else o[1] if k == 2 else 0.0
        if 1110 <= n <= 1118:
            g = self.g28
            if g is None:
                return 0.0
            k = n - 1110
            return (g[0] if g[0] is not None else 0.0) if k == 0 else \
                (g[1] if g[1] is not None else 0.0) if k == 2 else 0.0
        if 1150 <= n <= 1169:
            grp = n - 1150
            return float(self._modal(grp))
        raise EvalError(f"undefined variable #{n}: this system variable is not provided")

    def _modal(self, grp: int) -> int:
        if grp == 0:
            return self.last_g00
        if grp in (1, 2):  # appendix %0080 saves the motion code from #1152
            return self.motion
        return {8: 20 if self.unit != 1.0 else 21, 9: self.comp, 11: self.wcs,
                13: 90 if self.absolute else 91, 14: 95 if self.per_rev else 94,
                16: 36 if self.diam else 37, 17: 96 if self.css else 97}.get(grp, 0)

    def _write(self, n: float, v, line: int, col: int) -> None:
        if isinstance(n, float) and not n.is_integer() or n != n:
            raise self.alarm(f"invalid variable #{n:g}: not an integer", line, col)
        n = int(n)
        if 0 <= n < 50:
            self.L[n] = v
        elif 50 <= n < 200:
            self.G[n] = v
        elif 200 <= n < 600:
            lv, j = divmod(n - 200, 50)
            self.levels[lv][j] = v
        elif 600 <= n < 900:
            k, r = divmod(n - 600, 100)
            if k == 2:
                self.life[r] = v
            elif r == 0:
                raise self.alarm(f"variable #{n} is read-only (register 00 is no offset)", line, col)
            else:
                reg = self._register(r)
                from dataclasses import replace
                if k == 0:
                    self.regs[r] = replace(reg, z=float(v))
                else:
                    if v < 0:
                        raise self.alarm(f"nose radius #{n} cannot be negative", line, col)
                    self.regs[r] = replace(reg, radius=float(v))
                self._set_tool_delta()
        elif 1040 <= n <= 1099 and (n - 1040) % 10 in (0, 2):
            g, k = divmod(n - 1040, 10)
            o = self.wcs_tab.get(54 + g, (0.0, 0.0))
            self.wcs_tab[54 + g] = (float(v), o[1]) if k == 0 else (o[0], float(v))
            self._set_origin()
        elif 2000 <= n <= 2600:
            self.table[n - 2000] = v
        elif 1000 <= n < 1200:
            raise self.alarm(f"variable #{n} is read-only", line, col)
        else:
            raise self.alarm(f"undefined variable #{n}: no such variable (see manual 3.4.1)", line, col)

    def _arflag(self, n) -> float:
        if isinstance(n, float) and not n.is_integer():
            raise EvalError(f"invalid variable #{n:g} in AR[]")
        n = int(n)
        if 0 <= n < 50:
            return float(self.ars[self.level][n])
        return 0.0

