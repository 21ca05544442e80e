"""Planning: operation choice (face, G71 I/II, G72, G73, bore, finish, groove, thread),
cutting data and compensation mode; ``generate`` renders and checks the program.

Entry points: :func:`hnc_cam.plan.api.generate` (also ``hnc_cam.generate``) and
:func:`hnc_cam.plan.planner.make_plan`.
"""
from .model import Block, Operation, Plan
from .planner import Options, make_plan

__all__ = ["Block", "Operation", "Options", "Plan", "make_plan", "generate", "Program"]


def __getattr__(name):
    if name in ("generate", "Program", "VerificationError"):
        from . import api
        return getattr(api, name)
    raise AttributeError(name)
