//! KUKA FRAME arithmetic: X, Y, Z in mm and A, B, C in degrees
//! (R = Rz(A)·Ry(B)·Rx(C)), composition, inversion and comparison.

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
    pub const IDENTITY: Pose = Pose { x: 0.0, y: 0.0, z: 0.0, a: 0.0, b: 0.0, c: 0.0 };

    /// Builds a pose from its six components.
    pub fn new(x: f64, y: f64, z: f64, a: f64, b: f64, c: f64) -> Self {
        Pose { x, y, z, a, b, c }
    }

    /// The six components as an array `[x, y, z, a, b, c]`.
    pub fn to_array(&self) -> [f64; 6] {
        [self.x, self.y, self.z, self.a, self.b, self.c]
    }

    /// `self · other` (KRL's `:` operator): `other` expressed in `self`.
    pub fn compose(&self, other: &Pose) -> Pose {
        todo!("helper: implement")
    }

    /// The inverse frame (KRL `INV_POS`).
    pub fn inverse(&self) -> Pose {
        todo!("helper: implement")
    }

    /// Euclidean distance of the positions in mm.
    pub fn distance_mm(&self, other: &Pose) -> f64 {
        todo!("helper: implement")
    }

    /// Angle in degrees of the rotation between the two orientations
    /// (compares rotations, not components: correct at B = ±90°).
    pub fn angle_deg(&self, other: &Pose) -> f64 {
        todo!("helper: implement")
    }

    /// True if position within `mm` and orientation within `deg`.
    pub fn approx_eq(&self, other: &Pose, mm: f64, deg: f64) -> bool {
        self.distance_mm(other) <= mm && self.angle_deg(other) <= deg
    }
}
