#!/usr/bin/python3
"""Session 21: re-anchor every tracked frame on its latest keyframe after BA, ORB-SLAM style (docs/vo.md, session 21).

  session21_reanchor_on_keyframes.py RUN/trajectory.tum RUN/keyframes.tum OUT.tum

Each frame keeps its pose relative to the latest keyframe at or before it (as tracked) and takes that
keyframe's final pose. Standard library only.
"""
import sys, math
def q2R(x,y,z,w):
    return [[1-2*(y*y+z*z),2*(x*y-z*w),2*(x*z+y*w)],[2*(x*y+z*w),1-2*(x*x+z*z),2*(y*z-x*w)],[2*(x*z-y*w),2*(y*z+x*w),1-2*(x*x+y*y)]]
def R2q(R):
    tr=R[0][0]+R[1][1]+R[2][2]
    if tr>0:
        s=math.sqrt(tr+1)*2; return ((R[2][1]-R[1][2])/s,(R[0][2]-R[2][0])/s,(R[1][0]-R[0][1])/s,0.25*s)
    i=max(range(3),key=lambda k:R[k][k]); j=(i+1)%3; k=(i+2)%3
    s=math.sqrt(1+R[i][i]-R[j][j]-R[k][k])*2; q=[0,0,0]; q[i]=0.25*s; q[j]=(R[j][i]+R[i][j])/s; q[k]=(R[k][i]+R[i][k])/s
    return (q[0],q[1],q[2],(R[k][j]-R[j][k])/s)
def load(f):
    d={}
    for l in open(f):
        if l.startswith('#') or not l.strip(): continue
        v=[float(x) for x in l.split()]; d[round(v[0],4)]=(q2R(*v[4:8]),v[1:4])
    return d
def mul(A,B):
    R=[[sum(A[0][i][k]*B[0][k][j] for k in range(3)) for j in range(3)] for i in range(3)]
    t=[sum(A[0][i][k]*B[1][k] for k in range(3))+A[1][i] for i in range(3)]
    return (R,t)
def inv(A):
    RT=[list(r) for r in zip(*A[0])]; return (RT,[-sum(RT[i][k]*A[1][k] for k in range(3)) for i in range(3)])
tr=load(sys.argv[1]); kf=load(sys.argv[2]); out=open(sys.argv[3],'w')
kts=sorted(kf); 
for t in sorted(tr):
    ks=[k for k in kts if k<=t+1e-6 and k in tr]
    if not ks: P=tr[t]
    else:
        k=ks[-1]; P=mul(mul(kf[k],inv(tr[k])),tr[t])
    q=R2q(P[0]); out.write('%.6f %.6f %.6f %.6f %.9f %.9f %.9f %.9f\n'%(t,*P[1],*q))
