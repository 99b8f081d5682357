"""Rigid-body dynamics from a description of bodies and joints.

``Model.load(path)`` reads a ``.chain``, URDF or MJCF file and evaluates it with the interpreted
reference dynamics; ``generate(path, outputs=[...])`` builds the model's generated, specialized
code with cargo and returns an object with the same methods. Every method takes one state
(``(nq,)``, ``(nv,)``) or a batch (``(B, nq)``, ``(B, nv)``) and runs batches on all cores with
the interpreter's lock released.

Conventions that differ from Pinocchio's (``PINOCCHIO_NAMES`` maps the names):

- spatial vectors and Jacobian rows are angular first, ``[ω; v]`` (Pinocchio: linear first);
- ``bias`` is ``N(q, v)·v`` without gravity (Pinocchio's ``nle`` includes gravity: that is our
  ``nonlinear_effects``);
- the quaternion free base is ``[x, y, z, w, qx, qy, qz]`` (Pinocchio's free flyer:
  ``[x, y, z, qx, qy, qz, qw]``), a quaternion spherical joint ``[w, x, y, z]``;
- a URDF ``continuous`` joint is one angle (Pinocchio stores ``(cos θ, sin θ)``);
- the Euler free base (``floating="euler"``) has no Pinocchio joint;
- Pinocchio's URDF parser may order a link's child joints differently (by name).

``Model.to_pinocchio_q``/``from_pinocchio_q`` and ``to_pinocchio_v``/``from_pinocchio_v``
convert.
"""

from ._native import Error, Model, __version__  # noqa: F401
from ._generate import generate, outputs  # noqa: F401

#: Pinocchio's function (``pinocchio.<name>``) for each method of ``Model``, and what differs.
PINOCCHIO_NAMES = {
    "rnea": ("inverse_dynamics", "same values"),
    "aba": ("forward_dynamics", "same values"),
    "crba": ("mass_matrix", "same values"),
    "nonLinearEffects": ("nonlinear_effects", "same values"),
    "computeGeneralizedGravity": ("gravity", "same values"),
    "computeCoriolisMatrix": ("coriolis_matrix", "same values"),
    "computeMinverse": ("mass_matrix_inverse", "same values"),
    "computeRNEADerivatives": ("inverse_dynamics_derivatives", "(dtau_dq, dtau_dv)"),
    "computeABADerivatives": ("forward_dynamics_derivatives", "(ddq_dq, ddq_dv, Minv)"),
    "centerOfMass": ("center_of_mass", "same values"),
    "jacobianCenterOfMass": ("center_of_mass_jacobian", "same values"),
    "computeCentroidalMomentum": ("centroidal_momentum", "angular first"),
    "computeCentroidalMap": ("centroidal_momentum_matrix", "angular rows first"),
    "computeCentroidalMomentumTimeVariation": ("centroidal_momentum_rate", "angular first"),
    "computeKineticEnergy": ("kinetic_energy", "same values"),
    "computePotentialEnergy": ("potential_energy", "same values"),
    "updateFramePlacement": ("frame_placement", "(R, p) arrays for an SE3"),
    "getFrameVelocity": ("frame_velocity", "LOCAL, angular first"),
    "getFrameClassicalAcceleration": ("frame_acceleration", "LOCAL_WORLD_ALIGNED, angular first"),
    "getFrameJacobian": ("frame_jacobian", "angular rows first; reference='local'|'world'|'local_world_aligned'"),
    "getFrameJacobianTimeVariation": ("frame_jacobian_time_variation", "angular rows first"),
    "constraintDynamics": ("constrained_forward_dynamics", "contacts by frame name; angular first"),
    "impulseDynamics": ("impulse_dynamics", "contacts by frame name; angular first"),
}

__all__ = ["Error", "Model", "generate", "outputs", "PINOCCHIO_NAMES", "__version__"]
