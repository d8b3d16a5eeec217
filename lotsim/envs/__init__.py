"""Learning environments over lotsim's runs (the ``learn`` extra: Gymnasium and
PettingZoo; docs/learning.md).

``import lotsim.envs`` registers ``lotsim/ParkingOperator-v0`` with Gymnasium, so that
``gymnasium.make("lotsim/ParkingOperator-v0", scenario=...)`` makes it; or, without the
import, ``gymnasium.make("lotsim.envs:lotsim/ParkingOperator-v0", ...)``.

* :class:`ParkingOperatorEnv` (:mod:`lotsim.envs.operator`): the lot's operator chooses
  the slot of each car that comes, one step per choice;
* :func:`parallel_env` (:mod:`lotsim.envs.parallel`): the same run as a PettingZoo
  ``ParallelEnv`` whose agents are the cars;
* :mod:`lotsim.envs.baselines`: the run's own rankings and a random choice as policies,
  and the mean return of a policy over seeds;
* :mod:`lotsim.envs.episode`: what both environments are made of, in numpy alone.
"""

from __future__ import annotations

from lotsim.errors import LotsimError


class LearnUnavailable(LotsimError, ImportError):
    """Gymnasium or PettingZoo is not installed (the ``learn`` extra)."""


try:
    import gymnasium
except ImportError:
    raise LearnUnavailable("lotsim.envs needs gymnasium and pettingzoo: pip install "
                           "'lotsim[learn]'") from None

from lotsim.envs.episode import OperatorSettings, shipped_scenarios  # noqa: E402
from lotsim.envs.operator import ParkingOperatorEnv  # noqa: E402

OPERATOR_ID = "lotsim/ParkingOperator-v0"
"""The Gymnasium id of :class:`ParkingOperatorEnv`."""

if OPERATOR_ID not in gymnasium.registry:
    gymnasium.register(id=OPERATOR_ID, entry_point="lotsim.envs.operator:ParkingOperatorEnv")


def parallel_env(*args, **kwargs):
    """:class:`lotsim.envs.parallel.ParkingParallelEnv` (PettingZoo's ``parallel_env``
    convention)."""
    from lotsim.envs.parallel import ParkingParallelEnv

    return ParkingParallelEnv(*args, **kwargs)


__all__ = ["OPERATOR_ID", "LearnUnavailable", "OperatorSettings", "ParkingOperatorEnv",
           "parallel_env", "shipped_scenarios"]
