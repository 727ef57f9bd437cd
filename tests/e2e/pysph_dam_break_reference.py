#!/usr/bin/python3
"""Reference front positions x_max(t) of PySPH's 2D dam break (WCSPH scheme).

Runs Debian's PySPH example ``pysph.examples.dam_break_2d`` (package
python3-pysph 1.0~b1, ``apt-get install python3-pysph``) with its default
scheme (wcsph) and writes ``tests/e2e/data/pysph_dam_break_2d_dx<dx>.csv``
with the columns ``t,x_max,T,Z``:

    t      simulated time [s]
    x_max  largest x of the fluid particles [m] (raw PySPH coordinate)
    T      t*sqrt(2 g / a), g = 9.81, a = 1 (column width)
    Z      (x_max - x_wall)/a with x_wall = dx, the x of the fluid's initial
           leftmost particle column, so that Z(0) = 1 exactly (the initial
           rightmost fluid column is at x = 1 + dx).  The innermost left-wall
           particle layer is at x = 0; measured from the mid-point x = dx/2
           between wall and fluid instead, Z would be larger by dx/(2a).

Run with Debian's interpreter (it has numpy and pysph):

    /usr/bin/python3 tests/e2e/pysph_dam_break_reference.py --dx 0.03 --tf 0.8
    /usr/bin/python3 tests/e2e/pysph_dam_break_reference.py --dx 0.05 --tf 0.8

How long it takes (2-core machine, OMP_NUM_THREADS=2, another job running):
the first run compiles PySPH's generated Cython code (~30 s, cached in
~/.pysph afterwards); the solve to tf = 0.8 s then took 388 s (6.5 min) at
dx = 0.03 (4559 steps, 2278 fluid + 1660 wall particles) and 125 s at
dx = 0.05 (2734 steps, 861 + 1012 particles).

x_max is recorded after every time step by a post-step callback (it does
not change the time step); the CSV holds it linearly interpolated onto
t = 0, dt_out, 2 dt_out, ... (dt_out = 0.005 s by default; PySPH's own
adaptive step is ~1.9e-4 s at dx = 0.03, so interpolation error is far
below dx).

Deviation from the unmodified example: in PySPH 1.0b1, ``create_particles``
sets the particles' h and m from module globals computed from the default
dx = 0.03 (h = 0.039, m = 0.9), so ``--dx`` changes only the spacing (and the
initial dt via the scheme's h0).  The subclass below sets those globals to
h = hdx*dx and m = dx^2*rho0 from the chosen dx before the particles are
made; at dx = 0.03 this is identical to the unmodified example.  Everything
else (scheme, kernel, integrator, adaptive dt with cfl 0.3, n_damp = 50, the
example's output_at_times [0.4, 0.6, 0.8, 1.0], which shorten the step that
would cross those times) is the example's own.
"""

import argparse
import datetime
import os
import subprocess
import sys
import time

import numpy as np

import pysph
import pysph.examples.dam_break_2d as db


class RecordingDamBreak2D(db.DamBreak2D):
    """The example, with h and m following --dx and x_max recorded."""

    def create_particles(self):
        # The example's create_particles reads the module globals h and m.
        db.h = self.options.hdx * self.dx
        db.m = self.dx ** 2 * db.ro
        fluid, boundary = super().create_particles()
        self.initial = dict(
            fluid_x=fluid.x.copy(), fluid_y=fluid.y.copy(),
            boundary_x=boundary.x.copy(), boundary_y=boundary.y.copy(),
            h=float(fluid.h[0]), m=float(fluid.m[0]),
        )
        self.t_rec = [0.0]
        self.xmax_rec = [float(fluid.x.max())]
        return [fluid, boundary]

    def post_step(self, solver):
        # Called after integrator.step and before solver.t += dt.
        fluid = self.particles[0]
        self.t_rec.append(solver.t + solver.dt)
        self.xmax_rec.append(float(fluid.x.max()))


def pysph_version():
    try:
        deb = subprocess.run(
            ['dpkg-query', '-W', '-f=${Version}', 'python3-pysph'],
            capture_output=True, text=True).stdout.strip()
    except OSError:
        deb = ''
    return 'PySPH %s%s' % (pysph.__version__,
                           ' (Debian python3-pysph %s)' % deb if deb else '')


def describe_geometry(ini, dx):
    lines = []
    fx, fy = ini['fluid_x'], ini['fluid_y']
    ux, uy = np.unique(np.round(fx, 12)), np.unique(np.round(fy, 12))
    lines.append('fluid: %d particles, nx=%d x in [%.12g, %.12g] step %.12g,'
                 ' ny=%d y in [%.12g, %.12g] step %.12g, h=%g m=%g'
                 % (fx.size, ux.size, ux[0], ux[-1], np.diff(ux).mean(),
                    uy.size, uy[0], uy[-1], np.diff(uy).mean(),
                    ini['h'], ini['m']))
    bx, by = ini['boundary_x'], ini['boundary_y']
    ubx, uby = np.unique(np.round(bx, 12)), np.unique(np.round(by, 12))
    lines.append('boundary: %d particles, x values %d in [%.12g, %.12g],'
                 ' y values %d in [%.12g, %.12g]'
                 % (bx.size, ubx.size, ubx[0], ubx[-1], uby.size, uby[0],
                    uby[-1]))
    left = ubx[ubx <= 1e-9]
    right = ubx[ubx >= 4.0 - 1e-9]
    floor = uby[uby <= 1e-9]
    lines.append('left wall layers x = %s; right wall layers x = %s;'
                 ' floor layers y = %s'
                 % (list(np.round(left, 10)), list(np.round(right, 10)),
                    list(np.round(floor, 10))))
    return '\n'.join(lines)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    ap.add_argument('--dx', type=float, default=0.03)
    ap.add_argument('--tf', type=float, default=0.8)
    ap.add_argument('--dt-out', type=float, default=0.005,
                    help='spacing of the CSV rows in t [s]')
    ap.add_argument('--threads', type=int, default=2,
                    help='OpenMP threads (0: no OpenMP)')
    ap.add_argument('--workdir', default=None,
                    help='PySPH output dir (default /tmp/pysph_dam_break_dx<dx>)')
    ap.add_argument('--out', default=None, help='CSV path (default '
                    'tests/e2e/data/pysph_dam_break_2d_dx<dx>.csv)')
    args = ap.parse_args()

    here = os.path.dirname(os.path.abspath(__file__))
    tag = '%g' % args.dx
    out = args.out or os.path.join(here, 'data',
                                   'pysph_dam_break_2d_dx%s.csv' % tag)
    workdir = args.workdir or '/tmp/pysph_dam_break_dx%s' % tag

    argv = ['--dx', repr(args.dx), '--tf', repr(args.tf), '-d', workdir,
            '-q']
    if args.threads > 0:
        os.environ['OMP_NUM_THREADS'] = str(args.threads)
        argv.insert(0, '--openmp')
    else:
        argv.insert(0, '--no-openmp')

    app = RecordingDamBreak2D(fname='dam_break_2d')
    wall0 = time.time()
    app.run(argv)
    wall = time.time() - wall0

    t = np.asarray(app.t_rec)
    xmax = np.asarray(app.xmax_rec)
    n = int(np.floor(args.tf / args.dt_out + 1e-9))
    tg = np.arange(n + 1) * args.dt_out
    xg = np.interp(tg, t, xmax)
    a, g = db.fluid_column_width, db.g
    x_wall = float(np.min(app.initial['fluid_x']))
    T = tg * np.sqrt(2.0 * g / a)
    Z = (xg - x_wall) / a

    os.makedirs(os.path.dirname(out), exist_ok=True)
    cmd = ' '.join(['/usr/bin/python3', 'tests/e2e/pysph_dam_break_reference.py',
                    '--dx', repr(args.dx), '--tf', repr(args.tf)])
    with open(out, 'w') as f:
        f.write('# %s, pysph.examples.dam_break_2d default scheme (wcsph), '
                'h = 1.3*dx and m = dx^2*1000 following dx; command: %s; '
                'date: %s; %d steps, wall %.0f s; Z = (x_max - %.12g)/1 '
                '(x_wall = initial leftmost fluid x), T = t*sqrt(2*9.81/1); '
                'x_max interpolated from every step onto t\n'
                % (pysph_version(), cmd,
                   datetime.datetime.now().strftime('%Y-%m-%d %H:%M'),
                   len(t) - 1, wall, x_wall))
        f.write('t,x_max,T,Z\n')
        for row in zip(tg, xg, T, Z):
            f.write('%.4f,%.6f,%.6f,%.6f\n' % row)

    print(describe_geometry(app.initial, args.dx))
    print('steps %d, last dt %.4g s, wall time %.1f s (solve + setup)'
          % (len(t) - 1, np.diff(t)[-2] if len(t) > 2 else 0.0, wall))
    print('wrote', out)
    return 0


if __name__ == '__main__':
    sys.exit(main())
