"""The lesson's rich-motion Coulomb joint as a 500 Hz log with 12-bit angles, 5 % torque noise and optional pushes."""
import numpy as np
TRUE=dict(I=0.8,h=0.4,B=0.15,Fc=0.2,bias=0.0)
PUSHES=[(4.0,0.5,+1.0),(9.0,1.2,-1.0),(14.5,2.0,+1.0)]   # (start s, duration s, amplitude N m)
def synth_log(T=20.0, fs=500.0, seed=1, pushes=(), noise=0.05, quant=2*np.pi/4096):
    """Lesson's rich-motion Coulomb joint. The outside torque p(t) helps the motor:
    tau_motor = model - p."""
    rng=np.random.default_rng(seed); t=np.arange(0,T,1/fs)
    q=0.7*np.sin(1.3*t)+0.25*np.sin(2.7*t)
    qd=0.7*1.3*np.cos(1.3*t)+0.25*2.7*np.cos(2.7*t)
    qdd=-0.7*1.69*np.sin(1.3*t)-0.25*7.29*np.sin(2.7*t)
    tau=TRUE['I']*qdd+TRUE['h']*9.81*np.cos(q)+TRUE['B']*qd+TRUE['Fc']*np.sign(qd)+TRUE['bias']
    tau=tau+noise*np.sqrt(np.mean(tau**2))*rng.standard_normal(len(t))
    p=np.zeros_like(t)
    for t0,d,a in pushes:
        m=(t>=t0)&(t<=t0+d); p[m]+=a*0.5*(1-np.cos(2*np.pi*(t[m]-t0)/d))
    tau=tau-p
    qq=np.round(q/quant)*quant if quant else q
    return dict(t=t,q=qq,tau=tau,qd_log=None)
