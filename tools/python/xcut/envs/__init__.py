"""Gymnasium-style environments on xcut (docs/python.md#environments).

    from xcut.envs import IncisionEnv
    env = IncisionEnv()
    obs, info = env.reset(seed=0)
    obs, reward, terminated, truncated, info = env.step(env.action_space.sample())

They work without the gymnasium package; where it imports, they subclass gymnasium.Env and
"xcut/Incision-v0" is registered (gymnasium.make("xcut/Incision-v0")).
"""
from .incision import IncisionEnv, skin_scene
from .spaces import HAVE_GYMNASIUM

__all__ = ["IncisionEnv", "skin_scene", "HAVE_GYMNASIUM"]

if HAVE_GYMNASIUM:  # pragma: no cover - gymnasium is not one of Debian 12's packages
    import gymnasium

    if "xcut/Incision-v0" not in gymnasium.registry:
        gymnasium.register(id="xcut/Incision-v0", entry_point="xcut.envs.incision:IncisionEnv")
