"""The compiled peer: the hydraulic scene's right-hand side compiled by numba and integrated by
CyRK (a Cython Dormand-Prince: DOP853 or RK45), the way a Python user who needs speed would write
it. Used by `work_precision.py` (the paper scenes and the steel stops) and `sweep_cyrk.py` (the
design space's hydraulic runs).

The physics is `scene_scipy.py`'s (4 states: x_t, v_t, x_p, v_p; contacts switched inside the
right-hand side, no contact events). One run is compiled whole (`run`): the cruise in chunks
until a step passes the sensor, the sensor's time by regula falsi on re-integrations from the
last step before it, then the robot's segments (cruise to the brake, braking, standing), each
integrated to its end so that no step crosses a robot kink.

`setup()` returns `None` and a reason when numba or CyRK is missing (the benchmarks then skip the
peer), else a `Peer`. Its `args` vector carries what one run changes:

    [mode, t_brake, x_b, x_s, k_e, counter address, p10, dpk, m_p]

mode 0/1/2 cruise/brake/stand (set by `run`), the stops' stiffness `k_e` (N/m^1.5), the counter
of right-hand-side evaluations, the gas's preload pressure `p10` (Pa), the orifice's coefficient
`dpk = C0 rho (A_p / A_o)^2 / 2` (Pa s^2/m^2) and the object's mass `m_p` (kg).
"""

from dataclasses import dataclass
from typing import Any, Callable

import numpy as np

from lab import scene_scipy as ss

# the cruise is integrated in chunks of this length (s) until a step passes the sensor
CHUNK = 5e-4
N_ARGS = 9


def dpk(r_o: float) -> float:
    """The orifice's coefficient for an orifice of radius `r_o` (m)."""
    a_o = np.pi * r_o**2
    return 0.5 * ss.C0 * ss.RHO * (ss.A_P / a_o) ** 2


def args_for(counter: np.ndarray, k_e: float = ss.K_E, p10: float = ss.P10, r_o: float = ss.R_O,
             m_p: float = ss.M_P) -> np.ndarray:
    """The `args` vector of one run (mode and robot filled in by `run`)."""
    return np.array([0.0, 0.0, 0.0, 0.0, k_e, float(counter.ctypes.data), p10, dpk(r_o), m_p])


@dataclass
class Peer:
    run: Callable[..., Any]  # (addr, method, y0, args, rtol, atol, dead_time, chunk, t_end) -> (ok, v_p, t_detect)
    osc: Callable[..., Any]  # (addr, method, y0, args, rtol, atol, t_end) -> (ok, v)
    addr: dict
    version: str
    numba: str


def setup(osc_w: float, osc_zeta: float) -> tuple[Peer | None, str]:
    """Compile the peer (the damped oscillator `x'' + 2 zeta w x' + w^2 x = 0` too)."""
    try:
        import numba as nb
        from numba import types
        from numba.extending import intrinsic
        from CyRK import cyjit, nbsolve2_ivp
        import CyRK
    except Exception as e:  # noqa: BLE001
        return None, f"not installed ({type(e).__name__}: {e})"

    @intrinsic
    def counter_at(typingctx, addr):
        sig = types.CPointer(types.int64)(types.int64)

        def codegen(context, builder, signature, args):
            return builder.inttoptr(args[0], context.get_value_type(types.CPointer(types.int64)))
        return sig, codegen

    L, M_T, A_P, VG0, KAPPA, B = ss.L, ss.M_T, ss.A_P, ss.VG0, ss.KAPPA, ss.B
    K_C, CHI_C, CHI_E, V_MAX, A_BRAKE = ss.K_C, ss.CHI_C, ss.CHI_E, ss.V_MAX, ss.A_BRAKE
    W, Z = osc_w, osc_zeta

    @nb.njit(inline="always")
    def hc(k, chi, d, dd):
        if d <= 0.0:
            return 0.0
        f = d**1.5 * (k + chi * dd)
        return f if f > 0.0 else 0.0

    def scene_rhs(dy, t, y, args):
        cnt = counter_at(np.int64(args[5]))
        cnt[0] += 1
        mode = args[0]
        if mode == 0.0:
            x_r, v_r = V_MAX * t, V_MAX
        elif mode == 1.0:
            tau = t - args[1]
            x_r, v_r = args[2] + V_MAX * tau - 0.5 * A_BRAKE * tau * tau, V_MAX - A_BRAKE * tau
        else:
            x_r, v_r = args[3], 0.0
        k_e, p10, dpk_, m_p = args[4], args[6], args[7], args[8]
        s, sd = x_r - y[0], v_r - y[1]
        p1 = p10 * (VG0 / (VG0 - A_P * s)) ** KAPPA
        g = (p1 + dpk_ * sd * abs(sd)) * A_P + B * sd + hc(k_e, CHI_E, s - L, sd) - hc(k_e, CHI_E, -s, -sd)
        fc = hc(K_C, CHI_C, y[0] - y[2], y[1] - y[3])
        dy[0] = y[1]
        dy[1] = (g - fc) / M_T
        dy[2] = y[3]
        dy[3] = fc / m_p

    def osc(dy, t, y, args):
        cnt = counter_at(np.int64(args[5]))
        cnt[0] += 1
        dy[0] = y[1]
        dy[1] = -2.0 * Z * W * y[1] - W * W * y[0]

    addr = {"scene": cyjit(scene_rhs).address, "osc": cyjit(osc).address}

    @nb.njit
    def nj_solve(addr_, meth, t0, t1, y0, args, rtol, atol, h0):
        h0 = min(h0, 0.5 * abs(t1 - t0))  # CyRK takes a first step of at most half the span
        res = nbsolve2_ivp(addr_, (t0, t1), y0, method=meth, args=args, rtol=rtol, atol=atol, first_step=h0)
        ok = res.success
        t, y = res.t.copy(), res.y.copy()
        res.free()
        return ok, t, y

    V_SENS = ss.S_SENSOR

    @nb.njit
    def nj_run(addr_, meth, y0, args, rtol, atol, dead_time, chunk, t_end):
        """One run of the scene, all of it compiled: (ok, object final speed, t_detect; NaN
        if the sensor never switched)."""
        t, y, h = 0.0, y0.copy(), 0.0
        while True:  # the cruise in chunks until a step passes the sensor
            ok, ts, ys = nj_solve(addr_, meth, t, min(t + chunk, t_end), y, args, rtol, atol, h)
            if not ok:
                return False, 0.0, 0.0
            found = -1
            for i in range(ts.size):
                if V_MAX * ts[i] - ys[0, i] - V_SENS > 0.0:
                    found = i
                    break
            if found > 0:
                ta, ya, tb = ts[found - 1], ys[:, found - 1].copy(), ts[found]
                break
            if ts[-1] >= t_end:  # a strong gas spring: the sensor never switches, no brake
                return True, ys[3, -1], np.nan
            t, y, h = ts[-1], ys[:, -1].copy(), ts[-1] - ts[-2]
        h = tb - ta
        # the sensor's time: Illinois regula falsi on g(t) = v t - x_t(t) - s_sensor, x_t(t) by
        # integrating from the last step before it
        a, fa = ta, V_MAX * ta - ya[0] - V_SENS
        b = tb
        ok, ts, ys = nj_solve(addr_, meth, ta, b, ya, args, rtol, atol, b - ta)
        fb = V_MAX * b - ys[0, -1] - V_SENS
        td, yd = b, ys[:, -1].copy()
        side = 0
        for _ in range(80):
            if fb <= 0.0 or b - a <= 4e-16 * b:
                break
            c = (a * fb - b * fa) / (fb - fa)
            if not (a < c < b):
                c = 0.5 * (a + b)
            ok, ts, ys = nj_solve(addr_, meth, ta, c, ya, args, rtol, atol, c - ta)
            fc = V_MAX * c - ys[0, -1] - V_SENS
            if fc > 0.0:
                b, fb, td, yd = c, fc, c, ys[:, -1].copy()
                if side == -1:
                    fa *= 0.5
                side = -1
            else:
                a, fa = c, fc
                if side == 1:
                    fb *= 0.5
                side = 1
                if fc == 0.0:
                    td, yd = c, ys[:, -1].copy()
                    break
            if abs(fc) < 1e-17:
                break
        y = yd
        t_brake = td + dead_time
        t_stop = t_brake + V_MAX / A_BRAKE
        x_b = V_MAX * t_brake
        x_s = x_b + V_MAX * V_MAX / (2.0 * A_BRAKE)
        bounds = (td, t_brake, t_stop, t_end)
        for mode in range(3):
            a, b = min(bounds[mode], t_end), min(bounds[mode + 1], t_end)
            if b <= a:
                continue
            args[0], args[1], args[2], args[3] = float(mode), t_brake, x_b, x_s
            ok, ts, ys = nj_solve(addr_, meth, a, b, y, args, rtol, atol, h if mode == 0 else 0.0)
            if not ok:
                return False, 0.0, td
            y = ys[:, -1].copy()
        return True, y[3], td

    @nb.njit
    def nj_osc(addr_, meth, y0, args, rtol, atol, t_end):
        ok, ts, ys = nj_solve(addr_, meth, 0.0, t_end, y0, args, rtol, atol, 0.0)
        return ok, ys[1, -1]

    return Peer(run=nj_run, osc=nj_osc, addr=addr, version=CyRK.__version__, numba=nb.__version__), ""
