//! KUKA FRAME arithmetic: X, Y, Z in mm and A, B, C in degrees
//! (R = Rz(A)·Ry(B)·Rx(C)), composition, inversion and comparison.
//!
//! Internally every operation goes through a unit quaternion ([`DQuat`]), so
//! composition and comparison are exact at the gimbal lock B = ±90°, where
//! A and C are not unique. When a rotation is turned back into A/B/C at
//! B = ±90°, C is set to 0 and the whole rotation about the vertical goes
//! into A. Angles are returned in (−180°, 180°], B in [−90°, 90°].
//!
//! [`Pose::to_opw`] / [`Pose::from_opw`] convert to and from the
//! rs-opw-kinematics pose, which works in **meters**.

use rs_opw_kinematics::glam::{DMat3, DQuat, DVec3};
use rs_opw_kinematics::kinematic_traits::Pose as OpwPose;
use serde::{Deserialize, Serialize};

/// A KUKA FRAME: position in mm, orientation A/B/C in degrees about Z/Y/X.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
pub struct Pose {
    /// X in mm.
    pub x: f64,
    /// Y in mm.
    pub y: f64,
    /// Z in mm.
    pub z: f64,
    /// Rotation about Z in degrees.
    pub a: f64,
    /// Rotation about Y in degrees.
    pub b: f64,
    /// Rotation about X in degrees.
    pub c: f64,
}

impl Pose {
    /// The identity frame (all zero).
    pub const IDENTITY: Pose = Pose {
        x: 0.0,
        y: 0.0,
        z: 0.0,
        a: 0.0,
        b: 0.0,
        c: 0.0,
    };

    /// Builds a pose from its six components.
    pub fn new(x: f64, y: f64, z: f64, a: f64, b: f64, c: f64) -> Self {
        Pose { x, y, z, a, b, c }
    }

    /// The six components as an array `[x, y, z, a, b, c]`.
    pub fn to_array(&self) -> [f64; 6] {
        [self.x, self.y, self.z, self.a, self.b, self.c]
    }

    /// Position in mm as a vector.
    pub fn position(&self) -> DVec3 {
        DVec3::new(self.x, self.y, self.z)
    }

    /// Orientation as a unit quaternion: Rz(A)·Ry(B)·Rx(C).
    pub fn rotation(&self) -> DQuat {
        DQuat::from_rotation_z(self.a.to_radians())
            * DQuat::from_rotation_y(self.b.to_radians())
            * DQuat::from_rotation_x(self.c.to_radians())
    }

    /// Builds a pose from a position in mm and a rotation (normalised here).
    pub fn from_parts(position_mm: DVec3, rotation: DQuat) -> Self {
        let [a, b, c] = abc_from_quat(rotation.normalize());
        Pose {
            x: position_mm.x,
            y: position_mm.y,
            z: position_mm.z,
            a,
            b,
            c,
        }
    }

    /// The rs-opw-kinematics pose (translation in **meters**).
    pub fn to_opw(&self) -> OpwPose {
        OpwPose::from_parts(self.position() / 1000.0, self.rotation())
    }

    /// Converts an rs-opw-kinematics pose (meters) into a KUKA FRAME (mm, degrees).
    pub fn from_opw(pose: &OpwPose) -> Self {
        Self::from_parts(pose.translation * 1000.0, pose.rotation)
    }

    /// `self · other` (KRL's `:` operator): `other` expressed in `self`.
    pub fn compose(&self, other: &Pose) -> Pose {
        let q = self.rotation();
        Pose::from_parts(self.position() + q * other.position(), q * other.rotation())
    }

    /// The inverse frame (KRL `INV_POS`).
    pub fn inverse(&self) -> Pose {
        let qi = self.rotation().inverse();
        Pose::from_parts(-(qi * self.position()), qi)
    }

    /// Euclidean distance of the positions in mm.
    pub fn distance_mm(&self, other: &Pose) -> f64 {
        self.position().distance(other.position())
    }

    /// Angle in degrees of the rotation between the two orientations
    /// (compares rotations, not components: correct at B = ±90°).
    pub fn angle_deg(&self, other: &Pose) -> f64 {
        quat_angle(self.rotation(), other.rotation()).to_degrees()
    }

    /// True if position within `mm` and orientation within `deg`.
    pub fn approx_eq(&self, other: &Pose, mm: f64, deg: f64) -> bool {
        self.distance_mm(other) <= mm && self.angle_deg(other) <= deg
    }

    /// True if all six components are finite numbers.
    pub fn is_finite(&self) -> bool {
        self.to_array().iter().all(|v| v.is_finite())
    }
}

/// Angle in radians of the rotation taking `a` to `b` (0..=π).
pub(crate) fn quat_angle(a: DQuat, b: DQuat) -> f64 {
    // 2·atan2(|vector part|, |scalar part|) of a⁻¹·b is accurate at small angles,
    // unlike acos of the dot product.
    let d = a.inverse() * b;
    let v = DVec3::new(d.x, d.y, d.z).length();
    2.0 * v.atan2(d.w.abs())
}

/// KUKA A, B, C (degrees) of a unit quaternion, R = Rz(A)·Ry(B)·Rx(C).
fn abc_from_quat(q: DQuat) -> [f64; 3] {
    let m = DMat3::from_quat(q);
    // Column-major: m.x_axis = first column = (r00, r10, r20).
    let r00 = m.x_axis.x;
    let r10 = m.x_axis.y;
    let r20 = m.x_axis.z;
    let r01 = m.y_axis.x;
    let r11 = m.y_axis.y;
    let r21 = m.y_axis.z;
    let r22 = m.z_axis.z;
    let cos_b = r00.hypot(r10);
    let b = (-r20).atan2(cos_b);
    let (a, c) = if cos_b > 1e-9 {
        (r10.atan2(r00), r21.atan2(r22))
    } else {
        // Gimbal lock: only A ∓ C is defined; put it all into A (C = 0).
        // With C = 0: r01 = −sin A, r11 = cos A for either sign of B.
        ((-r01).atan2(r11), 0.0)
    };
    [clean_deg(a), clean_deg(b), clean_deg(c)]
}

/// Radians to degrees in (−180, 180], with −0 and −180 normalised.
fn clean_deg(rad: f64) -> f64 {
    let mut d = rad.to_degrees();
    if d <= -180.0 + 1e-12 {
        d += 360.0;
    }
    if d == 0.0 { 0.0 } else { d }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn assert_pose(p: &Pose, q: &Pose) {
        assert!(p.approx_eq(q, 1e-9, 1e-9), "{p:?} != {q:?}");
    }

    #[test]
    fn abc_round_trip_components() {
        for &(a, b, c) in &[
            (0.0, 0.0, 0.0),
            (10.0, 20.0, 30.0),
            (-170.0, 45.0, 179.0),
            (90.0, -89.0, -90.0),
            (180.0, 0.0, 0.0),
        ] {
            let p = Pose::new(1.0, 2.0, 3.0, a, b, c);
            let r = Pose::from_parts(p.position(), p.rotation());
            assert!((r.a - a).abs() < 1e-9, "{r:?}");
            assert!((r.b - b).abs() < 1e-9, "{r:?}");
            assert!((r.c - c).abs() < 1e-9, "{r:?}");
        }
    }

    #[test]
    fn rotation_order_is_z_y_x() {
        // A = 90° turns X into Y; B = 90° then turns the frame's X down (−Z).
        let p = Pose::new(0.0, 0.0, 0.0, 90.0, 0.0, 0.0);
        let x = p.rotation() * DVec3::X;
        assert!((x - DVec3::Y).length() < 1e-12);
        let p = Pose::new(0.0, 0.0, 0.0, 0.0, 90.0, 0.0);
        assert!((p.rotation() * DVec3::X - DVec3::NEG_Z).length() < 1e-12);
        assert!((p.rotation() * DVec3::Z - DVec3::X).length() < 1e-12);
    }

    #[test]
    fn gimbal_lock_compares_rotations() {
        // At B = 90° only A − C matters.
        let p = Pose::new(0.0, 0.0, 0.0, 30.0, 90.0, 10.0);
        let q = Pose::new(0.0, 0.0, 0.0, 20.0, 90.0, 0.0);
        assert!(p.angle_deg(&q) < 1e-6);
        let r = Pose::from_parts(p.position(), p.rotation());
        assert!((r.b - 90.0).abs() < 1e-6 && r.c == 0.0 && (r.a - 20.0).abs() < 1e-6);
        let p = Pose::new(0.0, 0.0, 0.0, 30.0, -90.0, 10.0);
        let r = Pose::from_parts(p.position(), p.rotation());
        assert!(p.angle_deg(&r) < 1e-6, "{r:?}");
    }

    #[test]
    fn compose_inverse() {
        let p = Pose::new(100.0, -20.0, 300.0, 30.0, -40.0, 170.0);
        let q = Pose::new(-5.0, 7.0, 11.0, -120.0, 10.0, 5.0);
        assert_pose(&p.compose(&p.inverse()), &Pose::IDENTITY);
        assert_pose(&p.inverse().compose(&p), &Pose::IDENTITY);
        let pq = p.compose(&q);
        assert_pose(&p.inverse().compose(&pq), &q);
        // A pure translation in a frame turned by A = 90° moves along Y.
        let f = Pose::new(10.0, 0.0, 0.0, 90.0, 0.0, 0.0);
        let g = f.compose(&Pose::new(5.0, 0.0, 0.0, 0.0, 0.0, 0.0));
        assert_pose(&g, &Pose::new(10.0, 5.0, 0.0, 90.0, 0.0, 0.0));
    }

    #[test]
    fn distance_and_angle() {
        let p = Pose::new(0.0, 0.0, 0.0, 0.0, 0.0, 0.0);
        let q = Pose::new(3.0, 4.0, 0.0, 0.0, 0.0, 25.0);
        assert!((p.distance_mm(&q) - 5.0).abs() < 1e-12);
        assert!((p.angle_deg(&q) - 25.0).abs() < 1e-9);
        let r = Pose::new(0.0, 0.0, 0.0, 179.0, 0.0, 0.0);
        let s = Pose::new(0.0, 0.0, 0.0, -179.0, 0.0, 0.0);
        assert!((r.angle_deg(&s) - 2.0).abs() < 1e-9);
    }

    #[test]
    fn opw_conversion_uses_meters() {
        let p = Pose::new(470.0, 0.0, 750.0, 0.0, 90.0, 0.0);
        let o = p.to_opw();
        assert!((o.translation - DVec3::new(0.47, 0.0, 0.75)).length() < 1e-12);
        assert_pose(&Pose::from_opw(&o), &p);
    }
}
