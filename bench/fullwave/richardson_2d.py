#!/usr/bin/python3
"""Does Richardson extrapolation (first order) of two FDTD resolutions converge near the edge? The 2-D half-plane
(halfplane2d.py) at 30, 60, 90 px/m against the exact series: the finer run's error, the error of
E_R = E_f + (E_f - E_c)/(r - 1) (r = res_f/res_c) and the estimate |E_f - E_c|/(r - 1) of the finer run's error.
  /usr/bin/python3 bench/fullwave/richardson_2d.py > bench/results/fullwave/richardson_2d.txt"""
import os
import sys
import math
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import halfplane2d as h, numpy as np, cases
obs=[]; meta=[]
for rho in cases.SHEET_RHOS_M:
  for a in cases.SHEET_ANGLES_DEG:
    obs.append((rho*math.cos(math.radians(a)), rho*math.sin(math.radians(a)))); meta.append((rho,a))
src=(0.5, math.sqrt(3)/2)
for pol in ['soft','hard']:
  hard=pol=='hard'
  ex = np.array([h.exact_ratio(rho, math.radians(a), 1.0, math.radians(60), hard) for rho,a in meta])
  f = {r: np.conj(h.fdtd_ratio(obs, src, hard, r, log=lambda s: None)) for r in (30,60,90)}
  for (c,fi) in [(30,60),(60,90)]:
    rr=fi/c; R = f[fi] + (f[fi]-f[c])/(rr-1)
    e_f=abs(f[fi]-ex); e_R=abs(R-ex); est=abs(f[fi]-f[c])/(rr-1)
    for rho in cases.SHEET_RHOS_M:
      idx=[i for i,(r_,a) in enumerate(meta) if r_==rho]
      print(pol, c, fi, rho, 'fine err med/max %.3f/%.3f'%(np.median(e_f[idx]),e_f[idx].max()), 'richardson err %.3f/%.3f'%(np.median(e_R[idx]),e_R[idx].max()), 'estimate %.3f/%.3f'%(np.median(est[idx]),est[idx].max()))
