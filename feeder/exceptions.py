"""Exceptions raised by feeder: one hierarchy, rooted at :class:`FeederError`.

Every error a user can provoke with bad input is a subclass of :class:`FeederError`, carries the
offending value in its message, and is raised at the boundary (:mod:`feeder.validation`) before
any library sees the input. This module imports nothing, so every layer may use it.
"""


class FeederError(Exception):
    """Base class of every exception raised by feeder."""


class InputError(FeederError, ValueError):
    """A numeric input is out of its range, not finite, or of the wrong shape."""


class OutputBusyError(FeederError):
    """Another run holds the lock of the output folder (:func:`feeder.files.exclusive_lock`)."""


class ElevationError(InputError):
    """An elevation outside the device's range [−4°, 70°]."""


class UrdfError(FeederError):
    """A URDF file is missing, malformed, or lacks what the model needs."""


class ClosureFrameError(UrdfError):
    """A frame named in a loop closure does not exist in the model."""


class ModelFolderError(UrdfError):
    """A file a model names (a mesh, a mesh's texture or material library) lies outside the
    model's folder once ``..`` and symbolic links are resolved: it is never read."""


class InertiaError(FeederError, ValueError):
    """A link's mass or inertia tensor is not physical.

    Attributes:
        link: Name of the offending link.
    """

    def __init__(self, link: str, reason: str):
        super().__init__(f"link '{link}': {reason}")
        self.link = link


class UnreachablePoseError(FeederError):
    """The closed loop cannot be assembled at the requested independent coordinates."""


class SingularPoseError(FeederError):
    """The pose is at or too near a singularity (toggle) for a meaningful answer.

    Attributes:
        sample: Index of the sample of a motion at or near the singular pose, when the error is
            about one sample of a motion (else None), so that a caller can name its time.
    """

    def __init__(self, message: str, sample: int | None = None):
        super().__init__(message)
        self.sample = sample


class ForwardDivergenceError(FeederError):
    """The forward run left the joints' end stops or blew up: the integration has diverged.

    The force-driven mechanism is unstable (a deviation grows like e^(4…6 t)), so a coarse step
    or a long cycle lets the integration error grow until the motion is no longer the one the
    loads were computed for.
    """


class ViewerPortError(FeederError):
    """The viewer's web port on 127.0.0.1 cannot be used (busy, or not permitted)."""


class FeederWarning(UserWarning):
    """Something in a user's input is legal but implausible (a body far heavier than the rest, an
    inertia no body of its size can have): the run goes on, the warning names the element."""
