"""Closed poses: assembly, the pose check, velocities, accelerations and continuation along a
motion. In the order of the data: :mod:`.newton` and :mod:`.rank` (the solvers and the linear
algebra), :mod:`.refusals` (the messages), :mod:`.check` (the pose check and its result),
:mod:`.partition` (the choice of independent joints, with :mod:`.restarts` for assembly from a
guess), :mod:`.continuation`, :mod:`.batch` and :mod:`.tracking` (following a motion into a
:mod:`.trajectory`)."""
