import OpenEXR, numpy as np, sys
def load(p):
    ch=OpenEXR.File(p).channels(); return np.asarray(ch['RGB'].pixels,dtype=np.float64)
ref=load(sys.argv[1]).mean(-1)
for a in sys.argv[2:]:
    im=load(a).mean(-1)
    e=(im-ref)/np.sqrt(ref**2+0.01)
    tot=(e**2).mean()
    out=[]
    for k in (2,4,8,16):
        H,W=e.shape; h,w=H//k*k,W//k*k
        blk=e[:h,:w].reshape(h//k,k,w//k,k).mean((1,3))
        out.append('%d:%.3f'%(k,(blk**2).mean()*k*k/tot))
    print(a,'relMSE %.3e'%tot,'blockvar*k^2/tot',' '.join(out))
