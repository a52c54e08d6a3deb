import OpenEXR, numpy as np, sys
def load(p):
    ch=OpenEXR.File(p).channels(); return np.asarray(ch['RGB'].pixels,dtype=np.float64)
ref=load(sys.argv[1])
def rel(im): return ((im-ref)**2/(ref**2+0.01)).mean()
for a,b in zip(sys.argv[2::2],sys.argv[3::2]):
    m=load(a); l=load(b)
    best=min((rel(w*l+(1-w)*m),w) for w in np.linspace(0,1,21))
    print(a, 'mlt %.3e'%rel(m),'large-as-pt %.3e'%rel(l),'best global w=%.2f %.3e'%(best[1],best[0]))
