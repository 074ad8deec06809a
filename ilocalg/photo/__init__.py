"""Photo positioning from points of interest (PoIs).

A user photographs PoIs whose world positions are known and drags each PoI's marker onto its
image; from the matched screen points the camera centre ``c`` follows by

- ST, similar triangles (:mod:`.similar_triangles`): linear least squares with a known orientation
  ``T_E->AR`` from accelerometer + magnetometer (i-Loc thesis eq. 29-30);
- VA, view angles (:mod:`.view_angle`): gradient descent on the PoI-pair view-angle mismatch,
  orientation-free, from a good or bad initial guess (VAGIG / VABIG);
- PnP (:mod:`.pnp`): OpenCV SQPnP, estimating orientation too (modern reference);
- homography (:mod:`.homography`): ``H = K [r1 r2 t]`` from a planar target (Ye and Huang's survey, eq. 3-5).

Frames and units are described in :mod:`.camera`.
"""

from ilocalg.photo.camera import (
    intrinsics,
    look_at,
    project,
    ray_angle_rad,
    rot_x,
    rot_y,
    rot_z,
    small_rotation,
    thin_lens_image_distance_m,
)
from ilocalg.photo.homography import (
    HomographyPose,
    homography_dlt,
    homography_dlt_batch,
    homography_locate,
    homography_pose,
    homography_pose_batch,
    wall_plane_coords,
)
from ilocalg.photo.pnp import PnPResult, pnp_solve, pnp_solve_batch, square_marker_pose
from ilocalg.photo.similar_triangles import (
    IllConditionedWarning,
    RankDeficientError,
    SimilarTriangles,
    STResult,
    st_error_propagation,
    st_solve,
    st_solve_batch,
    st_system,
)
from ilocalg.photo.view_angle import (
    VAResult,
    ViewAngle,
    measured_view_angles_rad,
    pair_index,
    va_cost,
    va_gradient,
    va_solve,
    va_solve_batch,
    view_angles_rad,
)

__all__ = [
    "intrinsics",
    "look_at",
    "project",
    "ray_angle_rad",
    "rot_x",
    "rot_y",
    "rot_z",
    "small_rotation",
    "thin_lens_image_distance_m",
    "HomographyPose",
    "homography_dlt",
    "homography_dlt_batch",
    "homography_locate",
    "homography_pose",
    "homography_pose_batch",
    "wall_plane_coords",
    "PnPResult",
    "pnp_solve",
    "pnp_solve_batch",
    "square_marker_pose",
    "IllConditionedWarning",
    "RankDeficientError",
    "SimilarTriangles",
    "STResult",
    "st_error_propagation",
    "st_solve",
    "st_solve_batch",
    "st_system",
    "VAResult",
    "ViewAngle",
    "measured_view_angles_rad",
    "pair_index",
    "va_cost",
    "va_gradient",
    "va_solve",
    "va_solve_batch",
    "view_angles_rad",
]
