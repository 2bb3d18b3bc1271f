"""Status codes of every service reply (the srv constants, one place) and their names."""

from __future__ import annotations

from wrenchcone_ros.conversions import CheckWrench

S = CheckWrench.Response  # status codes (GetCone and ClassifyWrench use the same values)
OK = S.OK
MODE_INFEASIBLE = S.MODE_INFEASIBLE
INVALID_MODE = S.INVALID_MODE
MODE_NOT_ALLOWED = S.MODE_NOT_ALLOWED
INVALID_WRENCH = S.INVALID_WRENCH
NO_INPUTS = S.NO_INPUTS
SCENE_ERROR = S.SCENE_ERROR
INTERNAL_ERROR = S.INTERNAL_ERROR
STATUS_NAMES = {
    OK: "OK", MODE_INFEASIBLE: "MODE_INFEASIBLE", INVALID_MODE: "INVALID_MODE",
    MODE_NOT_ALLOWED: "MODE_NOT_ALLOWED", INVALID_WRENCH: "INVALID_WRENCH",
    NO_INPUTS: "NO_INPUTS", SCENE_ERROR: "SCENE_ERROR", INTERNAL_ERROR: "INTERNAL_ERROR",
}
