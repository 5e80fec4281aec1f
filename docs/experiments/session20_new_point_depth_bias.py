#!/usr/bin/python3
"""Session 20: depth of new monocular map points against the rendered depth (docs/vo.md, session 20).

  session20_new_point_depth_bias.py TRACE SEQ

TRACE is what `PLLVO_DEPTH_TRACE=FILE pllvo run SEQ --mono --single-thread` writes with
session20_depth_trace_and_min_views.patch applied: per keyframe and map point it sees, the frame, the
point id, whether the keyframe created it, its observation count, its depth before the keyframe's BA,
its camera-frame position after it, its pixel and its parallax (deg). SEQ is a `pllvo synth --depth`
render (mav0/cam0/depth/*.png, 16-bit millimetres). Per keyframe, a point's ratio is its map depth over
the rendered depth at its projection; new points' ratios are divided by the median ratio of the points
the keyframe already had (the map's scale there) and summarised by views and parallax: 1 is unbiased,
below 1 too near. Standard library only.
"""
import sys, os, zlib, struct, statistics as st

def read16(p):
    d=open(p,'rb').read(); i=8; idat=b''
    while i<len(d):
        n=struct.unpack('>I',d[i:i+4])[0]; t=d[i+4:i+8]; c=d[i+8:i+8+n]
        if t==b'IHDR': w,h,bd,ct=struct.unpack('>IIBB',c[:10])
        if t==b'IDAT': idat+=c
        i+=12+n
    assert bd==16 and ct==0
    bpp=2; stride=w*bpp; raw=zlib.decompress(idat); prev=bytearray(stride); rows=[]
    for y in range(h):
        f=raw[y*(stride+1)]; line=raw[y*(stride+1)+1:(y+1)*(stride+1)]; out=bytearray(stride)
        for x in range(stride):
            a=out[x-bpp] if x>=bpp else 0; b=prev[x]; c=prev[x-bpp] if x>=bpp else 0; v=line[x]
            if f==1: v+=a
            elif f==2: v+=b
            elif f==3: v+=(a+b)//2
            elif f==4:
                pp=a+b-c; pa,pb,pc=abs(pp-a),abs(pp-b),abs(pp-c)
                v+= a if pa<=pb and pa<=pc else (b if pb<=pc else c)
            out[x]=v&255
        rows.append([out[2*k]*256+out[2*k+1] for k in range(w)]); prev=out
    return rows
trace, seq = sys.argv[1:3]
spec=seq+'/synth.yaml'; cam={}
for l in open(spec):
    l=l.strip()
    for k in ('fx','fy','cx','cy'):
        if l.startswith(k+':') and k not in cam: cam[k]=float(l.split(':')[1])
    if l.startswith('distortion:') and 'd' not in cam: cam['d']=[float(v) for v in l.split('[')[1].split(']')[0].split(',')]
ddir=seq+'/mav0/cam0/depth'; files=sorted(os.listdir(ddir))
rows={}
for l in open(trace):
    f,pid,new,nobs,zpre,x,y,z,u,v=l.split()[:10]; par=float(l.split()[10]) if len(l.split())>10 else 0; rows.setdefault(int(f),[]).append((int(new),int(nobs),float(zpre),float(x),float(y),float(z),par))
def proj(x,y,z):
    xn,yn=x/z,y/z; k1,k2,p1,p2=cam['d']; r2=xn*xn+yn*yn; rad=1+k1*r2+k2*r2*r2
    xd=xn*rad+2*p1*xn*yn+p2*(r2+2*xn*xn); yd=yn*rad+p1*(r2+2*yn*yn)+2*p2*xn*yn
    return cam['fx']*xd+cam['cx'], cam['fy']*yd+cam['cy']
by={}
for f in sorted(rows):
    if f<30: continue
    D=read16(os.path.join(ddir,files[f]))
    olds=[]; tmp=[]
    for new,nobs,zpre,x,y,z,par in rows[f]:
        if z<=0: continue
        u,v=proj(x,y,z); ui,vi=int(round(u)),int(round(v))
        if not(0<=ui<len(D[0]) and 0<=vi<len(D)) or D[vi][ui]==0: continue
        r=zpre/(D[vi][ui]/1000)
        if new: tmp.append((nobs,par,r))
        else: olds.append(r)
    if not olds: continue
    mo=st.median(olds)
    for nobs,par,r in tmp:
        b=min(int(par/0.5),8)
        by.setdefault((min(nobs,3),b),[]).append(r/mo)
for k in sorted(by):
    a=sorted(by[k]); n=len(a)
    print('views',k[0],'par %.1f-%.1f'%(k[1]*0.5,k[1]*0.5+0.5), n, 'median %.3f'%st.median(a), 'q10 %.3f q90 %.3f'%(a[n//10],a[9*n//10]), 'share<0.8: %.2f >1.25: %.2f'%(sum(r<0.8 for r in a)/n, sum(r>1.25 for r in a)/n))
