"""Converters between featherdyn's conventions and other libraries' (Pinocchio, Lynch–Park, Drake, ROS, MuJoCo).

featherdyn's conventions are fixed (docs/conventions.md): a motion is ``[ω; v_O]``
and a force ``[n_O; f]`` (angular first, Featherstone); ``PluckerTransform(R, p)``
is the pose of frame A in frame B and maps A- to B-coordinates; the free-flyer
``q`` is ``[x y z, qx qy qz qw]`` and its ``v`` is ``[ω; v]``, the base's spatial
velocity in base coordinates. Everything else converts here, at the boundary,
with a named pair of plain functions ``x_to_y`` / ``y_to_x`` (or
``to_y`` / ``from_y``) that undo each other. Array converters broadcast over
leading batch axes and keep float32 as float32; converters to another library's
*objects* (``pin.Motion``, ``pin.SE3``, ...) take one value at a time.

One module per library, every name also here (``featherdyn.conventions.NAME``):
:mod:`.pinocchio`, :mod:`.modern_robotics`, :mod:`.drake` (with the classical
acceleration), :mod:`.ros`, :mod:`.mujoco` (with the quaternion order).
The 6D swap used for Pinocchio and for flattened ROS messages is the
permutation ``P = [[0, 1], [1, 0]]`` (3×3 blocks), its own inverse::

    x_pin = P x,   M_pin = P M P,   J_pin = P J

=====================================  =====================================  ==========================================================
featherdyn → other                     other → featherdyn                     what changes
=====================================  =====================================  ==========================================================
**Pinocchio** (linear first)
``motion_to_pinocchio``                ``motion_from_pinocchio``              ``[ω; v]`` ↔ ``[v; ω]`` (raw ``(..., 6)``)
``force_to_pinocchio``                 ``force_from_pinocchio``               ``[n; f]`` ↔ ``[f; n]`` (raw ``(..., 6)``)
``matrix6_to_pinocchio``               ``matrix6_from_pinocchio``             ``P M P`` for any 6×6 map (X, X*, crm, inertia)
``jacobian_to_pinocchio``              ``jacobian_from_pinocchio``            rows ``P J`` (and free-flyer columns)
``freeflyer_v_to_pinocchio``           ``freeflyer_v_from_pinocchio``         ``[ω; v]`` ↔ ``[v; ω]`` (both base frame = LOCAL)
``to_pinocchio_motion``                ``from_pinocchio_motion``              ``SpatialMotion`` ↔ ``pin.Motion(linear, angular)``
``to_pinocchio_force``                 ``from_pinocchio_force``               ``SpatialForce`` ↔ ``pin.Force(linear, angular)``
``to_pinocchio_inertia``               ``from_pinocchio_inertia``             ``SpatialInertia`` ↔ ``pin.Inertia(mass, lever, inertia)``
``transform_to_pinocchio_se3``         ``transform_from_pinocchio_se3``       ``PluckerTransform`` ↔ ``pin.SE3`` (same semantics)
(free-flyer ``q``)                     (free-flyer ``q``)                     none: both ``[x y z, qx qy qz qw]``
``continuous_q_to_pinocchio``          ``continuous_q_from_pinocchio``        ``θ`` ↔ ``(cos θ, sin θ)``
``planar_q_to_pinocchio``              ``planar_q_from_pinocchio``            ``[x, y, θ]`` ↔ ``[x, y, cos θ, sin θ]``
``planar_v_to_pinocchio``              ``planar_v_from_pinocchio``            ``[ω, v_x, v_y]`` ↔ ``[v_x, v_y, ω]``
**Lynch–Park / Modern Robotics**
``twist_to_mr``                        ``twist_from_mr``                      none: both ``[ω; v]``
``wrench_to_mr``                       ``wrench_from_mr``                     none: both ``[m; f]``
``body_twist_to_spatial_twist``        ``spatial_twist_to_body_twist``        ``V_s = [Ad_T] V_b``
``adjoint_matrix``                     —                                      ``[Ad_T] = X.matrix()``
``ad_matrix``                          —                                      ``[ad_V] = crm(V)``
``wrench_transform_matrix``            —                                      ``[Ad_T]⁻ᵀ = X.dual_matrix()``
**Drake** (monogram names)
``spatial_to_classical_acceleration``  ``classical_to_spatial_acceleration``  linear part ``± ω × v_O``
``drake_shift_velocity``               (shift by ``−p``)                      ``v_Bq = v_Bo + ω × p``
``drake_shift_force``                  (shift by ``−p``)                      ``τ_Bq = τ_Bo − p × f``
``drake_shift_acceleration``           (shift by ``−p``)                      ``a_Bq = a_Bo + α × p + ω × (ω × p)``
``drake_reexpress``                    (with ``R_AEᵀ``)                       both halves rotated
**Drake** (a ``MultibodyPlant``'s state; a ``DrakeLayout`` places each joint)
``freeflyer_q_to_drake``               ``freeflyer_q_from_drake``             ``[x y z, qx qy qz qw]`` ↔ ``[qw qx qy qz, x y z]``
``freeflyer_v_to_drake``               ``freeflyer_v_from_drake``             ``[ω_b; v_b]`` ↔ ``[R ω_b; R v_b]`` (world axes)
``q_to_drake``                         ``q_from_drake``                       ``q`` ↔ plant positions (joint order, free joints)
``v_to_drake``                         ``v_from_drake``                       ``v_drake = V v``
``a_to_drake``                         ``a_from_drake``                       ``v̇_drake = V a + V̇ v``
``tau_to_drake``                       ``tau_from_drake``                     ``τ_drake = V τ``
``generalized_gravity_to_drake``       ``generalized_gravity_from_drake``     ``τ_g = −V g`` (``CalcGravityGeneralizedForces``)
``joint_matrix_to_drake``              ``joint_matrix_from_drake``            ``M_drake = V M Vᵀ`` (``CalcMassMatrix``)
``velocity_to_drake``                  ``velocity_from_drake``                ``V_WF_W`` ↔ ``[ω; v]`` in LOCAL / WORLD / LOCAL_WORLD_ALIGNED
``jacobian_to_drake``                  ``jacobian_from_drake``                ``J = W J_drake V`` (``CalcJacobianSpatialVelocity``)
``drake_velocity_map``                 —                                      ``V``: the permutation, ``blockdiag(R, R)`` on free joints
**ROS** (``geometry_msgs``)
``motion_to_ros_twist``                ``motion_from_ros_twist``              ``{"linear", "angular"}`` mapping
``force_to_ros_wrench``                ``force_from_ros_wrench``              ``{"force", "torque"}`` mapping
``twist_array_to_ros``                 ``twist_array_from_ros``               flattened ``[v; ω]``
``wrench_array_to_ros``                ``wrench_array_from_ros``              flattened ``[f; τ]``
**MuJoCo** (free joint)
``freeflyer_q_to_mujoco``              ``freeflyer_q_from_mujoco``            quaternion ``(x, y, z, w)`` ↔ ``(w, x, y, z)``
``freeflyer_v_to_mujoco``              ``freeflyer_v_from_mujoco``            ``[ω_b; v_b]`` ↔ ``[R v_b; ω_b]``
**MuJoCo** (whole ``load_mjcf`` models)
``q_to_mujoco``                        ``q_from_mujoco``                      ``q`` ↔ ``qpos`` (ball and free quaternions reordered)
``v_to_mujoco``                        ``v_from_mujoco``                      ``v`` ↔ ``qvel`` (``v = T qvel``)
``a_to_mujoco``                        ``a_from_mujoco``                      ``a`` ↔ ``qacc`` (``a = T qacc + Ṫ qvel``)
``tau_to_mujoco``                      ``tau_from_mujoco``                    ``τ`` ↔ ``qfrc`` (``qfrc = Tᵀ τ``)
``joint_matrix_to_mujoco``             ``joint_matrix_from_mujoco``           ``M`` ↔ ``Tᵀ M T`` (``mj_fullM``)
``mujoco_velocity_map``                —                                      ``T``, identity but on free joints
**Quaternion order**
``quat_xyzw_to_wxyz``                  ``quat_wxyz_to_xyzw``                  component order only
**Derivative matrices** (``fd.rnea_derivatives`` & co.; last axis: the tangent of ``fd.integrate``)
``derivatives_to_pinocchio``           ``derivatives_from_pinocchio``         free-flyer tangent ``[ω; v]`` ↔ ``[v; ω]``
``derivatives_to_parent_tangent``      —                                      ``D · Ad(T)⁻¹``: the tangent in the parent (world) frame
``derivatives_to_coordinates``         ``derivatives_from_coordinates``       chain rule through ``q ⊕ δ`` (quaternion coordinates)
=====================================  =====================================  ==========================================================

Sources: Featherstone, *Rigid Body Dynamics Algorithms* (2008) ch. 2;
chapter §2–§3 and §7.2; Lynch & Park, *Modern Robotics* (2017) ch. 3 and 8;
the Pinocchio, Drake, ROS ``geometry_msgs`` and MuJoCo documentation.
"""

from __future__ import annotations

from ..errors import MissingDependencyError
from . import derivatives, drake, modern_robotics, mujoco, pinocchio, ros
from .derivatives import *  # noqa: F403  (each module's names, also here: its __all__)
from .drake import *  # noqa: F403
from .modern_robotics import *  # noqa: F403
from .mujoco import *  # noqa: F403
from .pinocchio import *  # noqa: F403
from .ros import *  # noqa: F403

__all__ = ["MissingDependencyError"]
__all__ += derivatives.__all__
__all__ += drake.__all__
__all__ += modern_robotics.__all__
__all__ += mujoco.__all__
__all__ += pinocchio.__all__
__all__ += ros.__all__
