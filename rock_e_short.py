import femslide
import time
t0=time.time()
try:
    res = femslide.simulate("/tmp/rv/rock_e.toml", **{"simulate.t_end": 0.5})
    print("ok", res["converged"], res["steps"])
except Exception as e:
    print("FAIL", e)
