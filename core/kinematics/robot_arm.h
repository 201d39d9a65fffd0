// SPDX-License-Identifier: MIT
// Serial 6-joint arms described by a standard DH table (PROGRAM-FORMAT.md): forward kinematics,
// the analytic inverse of the UR family (UR3/UR5/UR10 structure: a1 = a4 = a5 = a6 = 0,
// alpha = [pi/2, 0, 0, pi/2, -pi/2, 0]), the geometric Jacobian and paper 003's singularity
// parameter (Eq. 5).
#pragma once
#include <Eigen/Core>
#include <array>

#include "machine/machine.h"

namespace omnislice {

using JointValues = std::array<double, 6>;  // radians

// Pose of the flange (DH frame 6) in the base frame (DH frame 0), mm.
Eigen::Matrix4d armForward(const DhTable& dh, const JointValues& q);

// next = frame times the standard DH link transform Rz(theta) Tz(d) Tx(a) Rx(alpha) of row, given
// ct, st = cos, sin(theta) and ca, sa = cos, sin(alpha): the product written out for the link's
// zeros (31 products instead of a 4x4 product's 64). frame's last row must be 0 0 0 1.
void appendDhLink(const Eigen::Matrix4d& frame, const DhRow& row, double ct, double st, double ca, double sa,
                  Eigen::Matrix4d& next);

// Poses of every DH frame 0..6 in the base frame (frames[0] = identity), for drawing the arm and
// for self-collision checks.
std::array<Eigen::Matrix4d, 7> armFrames(const DhTable& dh, const JointValues& q);

// True when dh has the UR-family structure urInverse() solves.
bool isUrFamily(const DhTable& dh);

// All analytic inverse-kinematics solutions of a UR-family arm for a flange pose: up to 8 branches
// (shoulder left/right x wrist up/down x elbow up/down), each joint wrapped to (-pi, pi]. Returns
// the number of solutions written; 0 when the pose is out of reach. Branch b's bits: 1 = shoulder,
// 2 = wrist, 4 = elbow (a branch keeps its index along a continuous motion away from singularities).
int urInverse(const DhTable& dh, const Eigen::Matrix4d& flange, JointValues solutions[8],
              int branches[8]);

// urInverse() restricted to the branches whose bit is set in branchMask (bit b = branch b; 0xff =
// all): the skipped branches cost nothing, so a caller that tracks one configuration is up to 8x
// faster. Same values and branch numbers as urInverse() for the branches it returns.
int urInverseBranches(const DhTable& dh, const Eigen::Matrix4d& flange, int branchMask,
                      JointValues solutions[8], int branches[8]);

// True when dh is an arm with a spherical wrist that sphericalWristInverse() solves (most
// industrial arms: ABB IRB, KUKA KR, Fanuc): d2 = d3 = d5 = 0, a4 = a5 = a6 = 0, alpha2 = 0 and
// alpha1, alpha3, alpha4, alpha5 = +-pi/2 (joints 2 and 3 parallel, joints 4-6 meeting in the wrist
// centre), a2 != 0; a1 (shoulder offset), a3 (elbow offset), d1, d4, d6 and the theta offsets free.
bool isSphericalWrist(const DhTable& dh);

// Analytic inverse of a spherical-wrist arm (Pieper): the wrist centre p - d6 z6 fixes joints 1-3
// (joint 1 from its azimuth, 2 and 3 as a planar two-link arm in the plane of joint 1), the
// orientation left for the wrist fixes 4-6. Up to 8 solutions, the same branch bits as urInverse
// (1 = shoulder: wrist centre in front of or behind the base axis, 2 = wrist flip, 4 = elbow),
// each joint wrapped to (-pi, pi]; branchMask as in urInverseBranches.
int sphericalWristInverseBranches(const DhTable& dh, const Eigen::Matrix4d& flange, int branchMask,
                                  JointValues solutions[8], int branches[8]);

// The analytic inverse of dh's structure: urInverseBranches for the UR family,
// sphericalWristInverseBranches for a spherical wrist, 0 solutions otherwise.
int armInverseBranches(const DhTable& dh, const Eigen::Matrix4d& flange, int branchMask,
                       JointValues solutions[8], int branches[8]);

// True when armInverseBranches solves dh (UR family or spherical wrist).
bool hasAnalyticInverse(const DhTable& dh);

// Geometric Jacobian at q in the base frame: rows 0-2 linear velocity of the flange origin in
// metres per radian (so the rows are commensurate with the angular ones), rows 3-5 angular.
Eigen::Matrix<double, 6, 6> armJacobian(const DhTable& dh, const JointValues& q);

// Paper 003 Eq. (5): w_PS = sqrt(s1 s2 ... s6) / (sqrt(s1) / sqrt(s6)) with s the singular values
// of J in descending order. It is 0 at a singular pose and grows away from singularities, so
// Omnislice keeps poses with the LARGEST w_PS (the paper's text says "minimise"; its own definition
// vanishes at singularities, so maximising is the reading that avoids them).
double singularityMeasure(const Eigen::Matrix<double, 6, 6>& jacobian);

}  // namespace omnislice
