#!/usr/bin/env python3
"""The SPH effects of stdlib/sph on a frozen 20 x 20 lattice (sph.part.in).

    sph_check.py PROGRAM KERNEL CPP

KERNEL is the one the scene chose, wendland_c2 or cubic_spline, and CPP the
C++ partc generated for it: its code (comments aside) names that kernel's
functions and none of the other's. Each run takes one step with dt = 0 and
writes the acceleration a, the density rate drho and the XSPH correction
the effects computed. Here they are recomputed pair by pair, with this
file's own kernels in 2D, q = r / h:
  Wendland C2:  W = 7 / (4 pi h^2) (1 - q/2)^4 (2q + 1)  for q < 2
  cubic spline: W = 10 / (7 pi h^2) (1 - 3/2 q^2 + 3/4 q^3)  for q < 1,
                    10 / (7 pi h^2) (2 - q)^3 / 4  for 1 <= q < 2
from the fields of sph.part.in's header, and their physics is checked:
- pressure: a uniform pressure gives no force in the interior (2h from the
  edge); any pressure field conserves momentum (sum m a = 0), and in the
  interior a approaches -grad p / rho;
- viscosity: conserves momentum and takes kinetic energy away (sum m v.a < 0);
- continuity: for v = U x e_x, drho = -rho0 div v = -rho0 U in the interior;
- Tait: p = B ((rho / rho0)^7 - 1), B = c0^2 rho0 / 7;
- XSPH: zero in the interior for a linear velocity field.
"""
import csv
import math
import subprocess
import sys
import tempfile
from pathlib import Path

N, DX = 20, 0.05
H = 1.3 * DX
RHO0, CS, ALPHA, EPS = 1000.0, 20.0, 0.1, 0.5
M = RHO0 * DX * DX


def wendland_c2(r):
    q = r / H
    return 7 / (4 * math.pi * H * H) * (1 - q / 2) ** 4 * (2 * q + 1) if q < 2 else 0.0


def wendland_c2_grad(r):  # -W'(r) / r, by differentiating W above
    q = r / H
    return 7 / (4 * math.pi * H * H) * 5 / (H * H) * (1 - q / 2) ** 3 if q < 2 else 0.0


def cubic_spline(r):
    q, a = r / H, 10 / (7 * math.pi * H * H)
    return (a * (1 - 1.5 * q * q + 0.75 * q ** 3) if q < 1 else
            a * (2 - q) ** 3 / 4 if q < 2 else 0.0)


def cubic_spline_grad(r):  # -W'(r) / r = -dW/dq / (h r), by differentiating W above
    q, a = r / H, 10 / (7 * math.pi * H * H)
    return (a * (3 * q - 2.25 * q * q) / (H * r) if q < 1 else
            a * 0.75 * (2 - q) ** 2 / (H * r) if q < 2 else 0.0)


KERNELS = {"wendland_c2": (wendland_c2, wendland_c2_grad),
           "cubic_spline": (cubic_spline, cubic_spline_grad)}


def check_code(cpp, chosen, failures):
    """The generated C++ without its comments (which quote the modules'
    if(kernel == 1, ...)) names the chosen kernel and not the other."""
    code = "\n".join(line.split("//")[0] for line in Path(cpp).read_text().splitlines())
    for name in KERNELS:
        named = name in code
        print(f"  the C++ names {name}: {named}")
        if named != (name == chosen):
            failures.append(f"the C++ of {chosen} {'names' if named else 'does not name'} {name}")


def run(program, folder, **params):
    out = Path(folder) / "state.csv"
    args = [a for k, v in params.items() for a in ("--set", f"{k}={v}")]
    subprocess.run([program, *args, "--steps", "1", "--output", str(out), "--quiet"], check=True)
    with open(Path(folder) / "state_F.csv", newline="") as f:
        rows = [{k: float(v) for k, v in row.items()} for row in csv.DictReader(f)]
    rows.sort(key=lambda row: row["id"])
    return rows


def fields(row, pamp, ramp, vkind, p0):
    x, y = row["p_0"], row["p_1"]
    pr = p0 * (1 + pamp * math.sin(3 * x + 1) * math.cos(2 * y))
    rho = RHO0 * (1 + ramp * math.sin(2 * x) * math.sin(5 * y + 2))
    v = ((math.cos(3 * x + 1) + y, math.sin(2 * y) - x) if vkind == 2 else
         (x, 0.0) if vkind == 1 else (0.0, 0.0))
    return x, y, pr, rho, v


def reference(rows, chosen, pamp, ramp, vkind, p0):
    """a (pressure + viscosity), drho and XSPH of every particle, pair by pair."""
    kernel, kernel_grad = KERNELS[chosen]
    f = [fields(row, pamp, ramp, vkind, p0) for row in rows]
    out = []
    for i, (xi, yi, pi, ri, vi) in enumerate(f):
        a, drho, corr = [0.0, 0.0], 0.0, [0.0, 0.0]
        for j, (xj, yj, pj, rj, vj) in enumerate(f):
            d = (xj - xi, yj - yi)
            r = math.hypot(*d)
            if r >= 2 * H:
                continue
            w = kernel(r)
            corr = [c + EPS * M / (0.5 * (ri + rj)) * (vj[k] - vi[k]) * w for k, c in enumerate(corr)]
            if j == i:
                continue
            g = kernel_grad(r)
            vdx = (vi[0] - vj[0]) * d[0] + (vi[1] - vj[1]) * d[1]
            visc = (ALPHA * CS * H * vdx / (r * r + 0.01 * H * H) / (0.5 * (ri + rj))
                    if vdx > 0 else 0.0)
            coef = M * (pi / ri ** 2 + pj / rj ** 2 + visc) * g
            a = [a[k] - coef * d[k] for k in range(2)]
            drho += M * g * vdx
        out.append((a, drho, corr))
    return out


def main():
    program, chosen, cpp = sys.argv[1:]
    failures = []
    print(f"kernel {chosen}:")
    check_code(cpp, chosen, failures)

    def check(what, got, want, tol):
        ok = abs(got - want) <= tol
        print(f"  {what}: {got:.6g} (want {want:.6g} within {tol:.3g}){'' if ok else '  FAILED'}")
        if not ok:
            failures.append(what)

    def interior(row):
        return all(3 * DX <= row[c] <= (N - 4) * DX + 1e-12 for c in ("p_0", "p_1"))

    cases = {
        "uniform pressure": dict(pamp=0, ramp=0, vkind=0, P0=1e4),
        "pressure field": dict(pamp=0.3, ramp=0, vkind=0, P0=1e4),
        "viscosity": dict(pamp=0, ramp=0.01, vkind=2, P0=0),
        "expansion": dict(pamp=0, ramp=0, vkind=1, P0=0),
    }
    with tempfile.TemporaryDirectory() as folder:
        for name, params in cases.items():
            print(f"{name} ({', '.join(f'{k} = {v}' for k, v in params.items())}):")
            rows = run(program, folder, **params)
            ref = reference(rows, chosen, params["pamp"], params["ramp"], params["vkind"], params["P0"])
            scale_a = max(math.hypot(*a) for a, _, _ in ref) or 1.0
            diff = max(math.hypot(row["acc_0"] - a[0], row["acc_1"] - a[1])
                       for row, (a, _, _) in zip(rows, ref))
            check("a against the pair sums here (max, relative)", diff / scale_a, 0, 1e-12)
            scale_d = max(abs(d) for _, d, _ in ref) or 1.0
            diff = max(abs(row["rate"] - d) for row, (_, d, _) in zip(rows, ref))
            check("drho against the pair sums here (max, relative)", diff / scale_d, 0, 1e-12)
            scale_c = max(math.hypot(*c) for _, _, c in ref) or 1.0
            diff = max(math.hypot(row["corr_0"] - c[0], row["corr_1"] - c[1])
                       for row, (_, _, c) in zip(rows, ref))
            check("xsph against the pair sums here (max, relative)", diff / scale_c, 0, 1e-12)
            total = sum(row["m"] * math.hypot(row["acc_0"], row["acc_1"]) for row in rows) or 1.0
            for k in (0, 1):
                momentum = sum(row["m"] * row[f"acc_{k}"] for row in rows)
                check(f"sum m a_{k} / sum m |a|", momentum / total, 0, 1e-12)
            b = CS * CS * RHO0 / 7
            worst = max(abs(row["pr"] - b * ((row["rho"] / RHO0) ** 7 - 1)) for row in rows)
            check("Tait: |p - B ((rho / rho0)^7 - 1)| / B", worst / b, 0, 1e-12)
            inner = [row for row in rows if interior(row)]
            if name == "uniform pressure":
                worst = max(math.hypot(row["acc_0"], row["acc_1"]) for row in inner)
                check("interior |a| / max |a| at the edge", worst / scale_a, 0, 1e-12)
            if name == "pressure field":
                worst = 0.0
                for row in inner:
                    x, y, _, rho, _ = fields(row, 0.3, 0, 0, 1e4)
                    grad = (1e4 * 0.3 * 3 * math.cos(3 * x + 1) * math.cos(2 * y),
                            -1e4 * 0.3 * 2 * math.sin(3 * x + 1) * math.sin(2 * y))
                    err = math.hypot(row["acc_0"] + grad[0] / rho, row["acc_1"] + grad[1] / rho)
                    worst = max(worst, err / (1e4 * 0.3 * 3 / RHO0))
                check("interior |a + grad p / rho| / max |grad p / rho|", worst, 0, 0.05)
            if name == "viscosity":
                power = sum(row["m"] * (row["v_0"] * row["acc_0"] + row["v_1"] * row["acc_1"])
                            for row in rows)
                print(f"  d(e_kin)/dt = sum m v.a = {power:.6g}")
                if not power < 0:
                    failures.append("viscosity dissipates")
            if name == "expansion":
                worst = max(abs(row["rate"] + RHO0) / RHO0 for row in inner)
                check("interior |drho + rho0 div v| / rho0", worst, 0, 0.03)
                worst = max(math.hypot(row["corr_0"], row["corr_1"]) for row in inner)
                check("interior |xsph| / (U dx)", worst / DX, 0, 1e-12)
    if failures:
        sys.exit("FAILED: " + ", ".join(failures))
    print("all checks passed")


if __name__ == "__main__":
    main()
