import OpenEXR, numpy as np, sys
def load(p):
    f=OpenEXR.File(p); ch=f.channels()
    if 'RGB' in ch: return np.asarray(ch['RGB'].pixels,dtype=np.float64)
    return np.stack([np.asarray(ch[c].pixels,dtype=np.float64) for c in 'RGB'],-1)
ref=load(sys.argv[1])
ims={a:load(a) for a in sys.argv[2:]}
lum=ref.mean(-1)
q=np.quantile(lum,[0.25,0.5,0.75])
bins=np.digitize(lum,q)
H=ref.shape[0]
for name,im in ims.items():
    e=((im-ref)**2/(ref**2+0.01)).mean(-1)
    tot=e.mean()
    print(name,'relMSE %.3e'%tot, 'top1%% share %.2f'%(np.sort(e.ravel())[::-1][:len(e.ravel())//100].sum()/e.sum()))
    print('  by lum quartile (mean relMSE):',' '.join('%.2e'%e[bins==b].mean() for b in range(4)))
    print('  by rows (6 bands):',' '.join('%.2e'%e[i*H//6:(i+1)*H//6].mean() for i in range(6)))
print('ref lum quartiles',q)
