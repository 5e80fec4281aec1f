#!/usr/bin/python3
"""ECD slider_hdr_close, frames 98-148: how many corners can a frame-based front end follow?

Session 9 measurement (docs/vo.md). For each start frame, 400 Shi-Tomasi corners (quality
0.001, 6 px apart, 5 x 5 blocks) on the 1 px-smoothed frame are tracked over three frames with
pyramidal LK (21 x 21, 3 levels), a 1 px forward-backward check and an NCC >= 0.75 check (the
pipeline's defaults); printed: start frame, corners, survivors, survivors that moved > 10 px
(the slider moves 9-10 px per frame), their median motion. The survivors that did not move are
the sensor's fixed pattern. Needs python3-opencv (not a project dependency: a one-off tool).
Run: /usr/bin/python3 docs/experiments/session9_ecd_texture_census.py [ECD_FOLDER]
"""
import sys
import cv2
import numpy as np

D = (sys.argv[1] if len(sys.argv) > 1 else '../shared/data/ecd_slider_hdr_close_149') + '/images/'
def load(i):
    im=cv2.imread(D+'frame_%08d.png'%i,0).astype(np.float32)
    return cv2.GaussianBlur(im,(0,0),1.0).astype(np.uint8)
def ncc(a,pa,b,pb,s=21):
    A=cv2.getRectSubPix(a,(s,s),tuple(map(float,pa))).astype(np.float32);B=cv2.getRectSubPix(b,(s,s),tuple(map(float,pb))).astype(np.float32)
    A-=A.mean();B-=B.mean();d=np.sqrt((A*A).sum()*(B*B).sum());return (A*B).sum()/d if d>0 else 0
for start in range(98,146,4):
    ims=[load(start+k) for k in range(4)]
    c=cv2.goodFeaturesToTrack(ims[0],400,0.001,6,blockSize=5)
    pts=c.reshape(-1,2); alive=np.ones(len(pts),bool); cur=pts.copy()
    for k in range(3):
        p,st,_=cv2.calcOpticalFlowPyrLK(ims[k],ims[k+1],cur.reshape(-1,1,2),None,winSize=(21,21),maxLevel=3)
        q,st2,_=cv2.calcOpticalFlowPyrLK(ims[k+1],ims[k],p,None,winSize=(21,21),maxLevel=3)
        p=p.reshape(-1,2);q=q.reshape(-1,2)
        ok=(st.ravel()==1)&(st2.ravel()==1)&(np.linalg.norm(q-cur,axis=1)<1)
        ok&=np.array([ncc(ims[k],cur[i],ims[k+1],p[i])>0.75 if ok[i] else False for i in range(len(p))])
        alive&=ok; cur=p
    f=np.linalg.norm(cur-pts,axis=1)
    print(start,len(pts),alive.sum(),(alive&(f>10)).sum(), np.median(f[alive&(f>10)]) if (alive&(f>10)).any() else 0)
