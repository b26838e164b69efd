#!/usr/bin/env python3
"""Whether the scans of a window, tied by the odometry, narrow the heading
at one step more than its own scan does (a diagnosis of the
hidden-ids woods runs). Needs numpy (the venv of `make test`).

    .venv/bin/python scripts/research/woods_window_pose.py MISSION.json RESULT.json STEP WINDOW [STRIDE]

A pose (th, p) of STEP (a grid of 61 headings x 31^2 positions over the
result's boxes) is kept when its scan's anchors (detections of groups
narrower than 0.6 m in the result) are reachable, as in
scripts/research/woods_pose_span.py, and when, for every step j = STEP +- d (d a
multiple of STRIDE up to WINDOW) with anchors, the pose predicted at j
lies within the odometry's tolerance of a pose that j's anchors allow
(j's own grid: 41 x 21^2). The prediction is *optimistic*: the true
relative pose (from the truth), widened only by the mission's heading
drift window b_k for k = |j - STEP| steps and its motion drift window
plus half the path length times b_k; the solver's relative evidence is
wider. Prints the headings kept after each j, then, for each non-anchor
detection of STEP whose true landmark has an earlier tight group, the
largest distance from its landmark points (over the kept poses) to the
far side of that group's box, against s. Floats: a diagnosis, not a proof.
"""
import json,sys,math
import numpy as np
if len(sys.argv) < 5:
    sys.exit(__doc__)
m=json.load(open(sys.argv[1])); r=json.load(open(sys.argv[2]))
sys.argv=[sys.argv[0]]+sys.argv[3:]
D=m['detections']; det=r['detections']; lab=m['truth']['matching']
o=m['sensor_offset'][0]; tp=m['truth']['positions']; th=m['truth']['headings']
hd=sorted((w['steps'],w['error']) for w in m['heading_drift'] if 'exempt_above' in w)
md=sorted((w['steps'],w['error']) for w in m['motion_drift'])
def win(tab,k,per):
    best=k*per
    for s,e in tab:
        if s>=k: best=min(best,e)
    return best
gbox={}
for g in r['matching']:
    x0=max(det[j][0][0] for j in g); x1=min(det[j][0][1] for j in g)
    y0=max(det[j][1][0] for j in g); y1=min(det[j][1][1] for j in g)
    for j in g: gbox[j]=(x0,x1,y0,y1)
bystep={}
for j,d in enumerate(D): bystep.setdefault(d['step'],[]).append(j)
TIGHT=0.6
def anchors(s): return [j for j in bystep.get(s,[]) if j in gbox and max(gbox[j][1]-gbox[j][0],gbox[j][3]-gbox[j][2])<TIGHT]
def feasible(s, TH, X, Y):
    """boolean array over broadcast (TH,X,Y): every anchor of step s reachable"""
    ok=np.ones(np.broadcast(TH,X,Y).shape,bool)
    sx=X+o*np.cos(TH); sy=Y+o*np.sin(TH)
    for j in anchors(s):
        B=gbox[j]; d=D[j]; R=d['range']; b=d['bearing']
        anyok=np.zeros_like(ok)
        for lx in np.linspace(B[0],B[1],5):
            for ly in np.linspace(B[2],B[3],5):
                vx=lx-sx; vy=ly-sy; rr=np.hypot(vx,vy)
                ang=np.mod(np.arctan2(vy,vx)-TH-b[0],2*math.pi)
                anyok|=(rr>=R[0])&(rr<=R[1])&(ang<=b[1]-b[0])
        ok&=anyok
    return ok
i=int(sys.argv[1]); W=int(sys.argv[2]); stride=int(sys.argv[3]) if len(sys.argv)>3 else 5
P=r['trajectory'][i]; H=r['headings'][i]
ths=np.linspace(H[0],H[1],61); xs=np.linspace(P[0][0],P[0][1],31); ys=np.linspace(P[1][0],P[1][1],31)
TH,X,Y=np.meshgrid(ths,xs,ys,indexing='ij')
alive=feasible(i,TH,X,Y)
print('step',i,'alone: headings',np.ptp(ths[alive.any(axis=(1,2))]).round(3))
path=0
for j in range(max(0,i-W),min(len(tp),i+W+1),stride):
    if j==i or not anchors(j) or tp[j] is None or tp[i] is None: continue
    k=abs(j-i)
    steps=range(min(i,j),max(i,j))
    L=sum(math.hypot(tp[a+1][0]-tp[a][0],tp[a+1][1]-tp[a][1]) for a in steps if tp[a] and tp[a+1])
    bh=win(hd,k,0.025); bm=win(md,k,0.0249*math.sqrt(2))+L*bh/2
    dH=th[j]-th[i]; c,s_=math.cos(-th[i]),math.sin(-th[i])
    vx=tp[j][0]-tp[i][0]; vy=tp[j][1]-tp[i][1]; Px=c*vx-s_*vy; Py=s_*vx+c*vy
    # feasible set at j on its own grid, as points
    Pj=r['trajectory'][j]; Hj=r['headings'][j]
    tj=np.linspace(Hj[0],Hj[1],41); xj=np.linspace(Pj[0][0],Pj[0][1],21); yj=np.linspace(Pj[1][0],Pj[1][1],21)
    T2,X2,Y2=np.meshgrid(tj,xj,yj,indexing='ij'); f=feasible(j,T2,X2,Y2)
    pts=np.stack([T2[f],X2[f],Y2[f]],1)
    if len(pts)==0: continue
    # predicted pose at j for each alive hypothesis
    idx=np.argwhere(alive)
    t0=ths[idx[:,0]]; x0=xs[idx[:,1]]; y0=ys[idx[:,2]]
    pt=t0+dH; px=x0+np.cos(t0)*Px-np.sin(t0)*Py; py=y0+np.sin(t0)*Px+np.cos(t0)*Py
    keep=np.zeros(len(idx),bool)
    # grid tolerance: half a cell of j's grid
    tt=bh+(tj[1]-tj[0]); tx=bm+(xj[1]-xj[0]); ty=bm+(yj[1]-yj[0])
    for a in range(0,len(idx),2000):
        sl=slice(a,a+2000)
        dt=np.abs(pt[sl,None]-pts[None,:,0])<=tt
        dx=np.abs(px[sl,None]-pts[None,:,1])<=tx
        dy=np.abs(py[sl,None]-pts[None,:,2])<=ty
        keep[sl]=(dt&dx&dy).any(1)
    alive[tuple(idx[~keep].T)]=False
    hs=ths[alive.any(axis=(1,2))]
    print(f' j={j} k={k} bh={bh:.3f} bm={bm:.3f} anchors={len(anchors(j))} alive={alive.sum()} heading span={np.ptp(hs) if len(hs) else None:.3f}')
# returning detections at i: far distance to own earlier tight box
idx=np.argwhere(alive); t0=ths[idx[:,0]]; x0=xs[idx[:,1]]; y0=ys[idx[:,2]]
print('truth heading',th[i],'kept',ths[alive.any(axis=(1,2))].min(),ths[alive.any(axis=(1,2))].max())
for j in bystep[i]:
    if j in anchors(i): continue
    d=D[j]; best=None
    olds=[k for k in gbox if lab[k]==lab[j] and D[k]['step']<i and max(gbox[k][1]-gbox[k][0],gbox[k][3]-gbox[k][2])<TIGHT]
    if not olds: continue
    B=gbox[olds[0]]
    far=0
    for rr in np.linspace(d['range'][0],d['range'][1],3):
        for bb in np.linspace(d['bearing'][0],d['bearing'][1],3):
            qx=o+rr*math.cos(bb); qy=rr*math.sin(bb)
            lx=x0+np.cos(t0)*qx-np.sin(t0)*qy; ly=y0+np.sin(t0)*qx+np.cos(t0)*qy
            dx=np.maximum(np.abs(lx-B[0]),np.abs(lx-B[1])); dy=np.maximum(np.abs(ly-B[2]),np.abs(ly-B[3]))
            far=max(far,np.hypot(dx,dy).max())
    print(f' detection {j} label {lab[j]} range {d["range"][0]:.2f}: far distance to earlier box {far:.2f} (s={m["landmark_min_separation"]:.2f})')
