#pragma once
/// Blend weights made continuous over the decoded surface where a pose bends it (DECISIONS 4,
/// "Posing"). pose_weights gives a point its weights from its location on its own segment's axis,
/// so they jump where the points of two segments meet; at a joint turned by theta a jump of dw
/// shears the surface by about dw * theta * r across one edge, and an arm whose segments near the
/// pivot are shorter than the blend width folds faces over each other there. Here the weights
/// of every point near a blend are refitted over a ball of the surface around it (moving least
/// squares of degree 1, kernel (1 - t^2)^2 of the straight distance, vertex areas as measure; the
/// ball: the points within its radius that the edges reach without leaving it): continuous where
/// the ball moves continuously, and a weight that already varies linearly is left as it was.
/// The radius: kPoseSmoothRadii of the point's segment's radius, or less where the blended
/// motions take the point to places closer together than that.
///
/// Only where motions differ: segments whose bones move alike (motion_groups) count as one, so a
/// point whose weights fall on one group and that no blending point's ball reaches stays exactly
/// as it was (it moves rigidly), and a joint's smoothing does not spread through a chain of
/// segments that move together. Only across joints: a point takes weight only from segments near
/// its own along the skeleton, not across a contact (two feet side by side).
///
/// Harmonic weights over the decoded mesh (a Laplace fill of the blending points from the rigid
/// ones) were tried first: on the decode's anisotropic tessellation (edges 0.009-0.14 on a capsule
/// of radius 1) even clamped cotangent weights left them 0.44-0.81 around the circumference at one
/// height, and a capsule's half twist crossed 30352 face pairs.
#include "libsdm/pose/pose_skeleton.h"
#include "libsdm/pose/pose_weights.h"

#include <Eigen/Core>
#include <vector>

namespace sdm {

/// The ball's largest radius in radii of the point's own segment: the smallest with which an arm
/// twisted 90 degrees adds no crossing face pair at its joint (tests/test_pose.cpp), the vertices
/// away from the pivot staying on the rigid motion (docs/BENCHMARKS.md).
constexpr double kPoseSmoothRadii = 0.5;
/// Weights under this are dropped after the smoothing and the rest renormalised.
constexpr double kPoseWeightFloor = 1e-4;

/// Per segment (= bone of `pose`), its motion group: the smallest segment index among the bones
/// that move alike (unit quaternions' |dot| within 1e-12 of 1, translations within 1e-9 of the rest
/// skeleton's extent, the same radius scale and no stretch), else its own index.
std::vector<int> motion_groups(const SkeletonPose& pose);

/// Smooths, in place, the weights of `w` (computed for `points`, the rest positions of the vertices
/// of `triangles`) as described above for `pose` (bones = the layout's segments); `layout`: the
/// layout the weights were computed on (its skeleton and radii). A smoothed point gets one entry
/// per group, on the group's first segment.
/// \throw std::invalid_argument when the sizes differ or a triangle names a point out of range.
void smooth_pose_weights(PoseWeights& w, const std::vector<Eigen::Vector3d>& points, const Eigen::MatrixX3i& triangles,
                         const SkeletonPose& pose, const Layout& layout);

/// The same for a rig, whose pose is not known: every segment its own group, the largest radius
/// wherever a point blends segments. Where a pose turns sub-trees rigidly, its smoothing touches a
/// subset of these points with balls no larger, so a vertex that the rig gives one joint moves as
/// sdm pose moves it.
void smooth_rig_weights(PoseWeights& w, const std::vector<Eigen::Vector3d>& points, const Eigen::MatrixX3i& triangles,
                        const Layout& layout);

}  // namespace sdm
