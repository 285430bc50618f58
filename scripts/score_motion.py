#!/usr/bin/env python3
"""Orientation error of a log against a pose file (t,elevation,azimuth,roll), as the two-arm check in
Tests/Cli/StageCliTests.cpp scores it (the file looped, poses interpolated, after the first second,
best lag -150..300 ms by RMS) but also printing the median and medians per window (issue 49).
usage: score_motion.py LOG.csv POSES.csv [QW_COLUMN_NAME_OR_INDEX]   (default column "qw";
the two-arm --arms-log: 1 for the right arm, 5 for the left; `fuse --out` files: qw)."""
import sys, csv, math, numpy as np
def qmul(a,b):
    w1,x1,y1,z1=a; w2,x2,y2,z2=b
    return np.array([w1*w2-x1*x2-y1*y2-z1*z2, w1*x2+x1*w2+y1*z2-z1*y2, w1*y2-x1*z2+y1*w2+z1*x2, w1*z2+x1*y2-y1*x2+z1*w2])
def about(deg, ax):
    h=math.radians(deg)/2; v=np.zeros(4); v[0]=math.cos(h); v[1+ax]=math.sin(h); return v
def pose2q(e,a,r): return qmul(qmul(about(90-a,1),about(e,2)),about(r,0))
def load_motion(f):
    rows=[]
    for r in csv.DictReader(open(f)): rows.append((float(r['t']),float(r['elevation']),float(r['azimuth']),float(r['roll'])))
    return np.array(rows)
def load_log(f, col):
    rd=csv.reader(open(f)); hdr=next(rd)
    c = hdr.index(col) if isinstance(col,str) else col
    out=[]
    for r in rd:
        try: t=float(r[0]); q=[float(x) for x in r[c:c+4]]
        except: continue
        if all(math.isfinite(x) for x in q): out.append([t]+q)
    return np.array(out)
def errors(log, mot, lag, t0=1.0):
    period=mot[-1,0]; errs=[]; ts=[]
    for row in log:
        t=row[0]
        if t<t0: continue
        u=math.fmod(t-lag,period)
        if u<0: u+=period
        k=min(max(np.searchsorted(mot[:,0],u,side='right')-1,0),len(mot)-2)
        f=min(max((u-mot[k,0])/(mot[k+1,0]-mot[k,0]),0),1)
        p=mot[k,1:]+f*(mot[k+1,1:]-mot[k,1:])
        tq=pose2q(*p); q=row[1:5]/np.linalg.norm(row[1:5])
        errs.append(2*math.degrees(math.acos(min(1,abs(q@tq))))); ts.append(t)
    return np.array(ts),np.array(errs)
if __name__=='__main__':
    log=load_log(sys.argv[1], sys.argv[3] if len(sys.argv)>3 and not sys.argv[3].isdigit() else int(sys.argv[3]) if len(sys.argv)>3 else 'qw')
    mot=load_motion(sys.argv[2])
    best=None
    for k in range(-30,61):
        ts,e=errors(log,mot,k*0.005)
        rms=math.sqrt((e**2).mean())
        if best is None or rms<best[0]: best=(rms,k*0.005,np.median(e),ts,e)
    rms,lag,med,ts,e=best
    print(f"rms {rms:.2f} median {med:.2f} lag {lag*1e3:.0f}ms n {len(e)}", end='')
    for a,b in [(1,5),(5,15),(15,30),(30,60),(60,1e9)]:
        m=(ts>=a)&(ts<b)
        if m.any(): print(f" | {a}-{b}s med {np.median(e[m]):.2f}", end='')
    print()
