//! What widgets draw over a map, in one frame: image units (`u` columns from
//! the left edge, `v` rows from the top edge of the north-up image, one unit
//! per cell) and image angles (radians clockwise from `+u`, which is a world
//! angle counter-clockwise from east, mirrored because `v` grows south). The
//! page draws these as they come: no flip, no scale, no trigonometry on the
//! model's numbers.

use crate::geometry::{GridGeometry, Pose};

/// A world angle (counter-clockwise from east) as an image angle.
#[inline]
pub fn image_angle(world: f64) -> f64 {
    -world
}

/// A robot over a map: where it is and which way it faces.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
#[serde(rename_all = "camelCase")]
pub struct RobotMark {
    /// Image units.
    pub x: f64,
    pub y: f64,
    /// Image angle of the heading, radians.
    pub heading: f64,
}

impl RobotMark {
    pub fn at(geometry: &GridGeometry, pose: &Pose) -> Self {
        let [x, y] = geometry.world_to_image(pose.x, pose.y);
        Self {
            x,
            y,
            heading: image_angle(pose.theta),
        }
    }
}

/// A cone or a beam from a point: its axis as an image angle, its reach in
/// cells, and its half opening angle (0 for a thin beam).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
#[serde(rename_all = "camelCase")]
pub struct RayMark {
    /// Image units.
    pub x: f64,
    pub y: f64,
    /// Image angle of the axis, radians.
    pub heading: f64,
    /// Length, cells.
    pub range: f64,
    /// Half the opening angle, radians.
    pub half_width: f64,
}

impl RayMark {
    /// The cone of half opening `half_width` (radians) and `range` metres
    /// from `pose` along bearing `bearing` (radians from the heading).
    pub fn from_pose(
        geometry: &GridGeometry,
        pose: &Pose,
        bearing: f64,
        range: f64,
        half_width: f64,
    ) -> Self {
        let [x, y] = geometry.world_to_image(pose.x, pose.y);
        Self {
            x,
            y,
            heading: image_angle(pose.theta + bearing),
            range: range / geometry.resolution(),
            half_width,
        }
    }

    /// The ray's far end in image units.
    pub fn end(&self) -> [f64; 2] {
        [
            self.x + self.range * self.heading.cos(),
            self.y + self.range * self.heading.sin(),
        ]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A ray's end in image units is the world end point's image: the
    /// mirrored angle and the flipped rows agree.
    #[test]
    fn a_ray_ends_where_its_world_end_point_is_drawn() {
        let g = GridGeometry::new(40, 30, 0.1, -1.0, -2.0).unwrap();
        let pose = Pose::new(0.5, -0.5, 0.7).unwrap();
        let ray = RayMark::from_pose(&g, &pose, 0.3, 1.2, 0.0);
        let (x, y) = pose.point_at(1.2, 0.3);
        let [u, v] = g.world_to_image(x, y);
        let [eu, ev] = ray.end();
        assert!(
            (eu - u).abs() < 1e-9 && (ev - v).abs() < 1e-9,
            "{eu},{ev} vs {u},{v}"
        );
        let robot = RobotMark::at(&g, &pose);
        assert_eq!([robot.x, robot.y], g.world_to_image(0.5, -0.5));
        assert_eq!(robot.heading, -0.7, "facing north-east is up and right");
    }
}

/// A cell of the north-up image: column from the left, row from the top.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
pub struct ImageCell {
    pub col: usize,
    pub row: usize,
}

impl ImageCell {
    /// Cell `(ix, iy)` of `geometry` (row 0 at the bottom) in the image.
    pub fn of(geometry: &GridGeometry, ix: usize, iy: usize) -> Self {
        Self {
            col: ix,
            row: geometry.height() - 1 - iy.min(geometry.height() - 1),
        }
    }
}

/// An image point.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct ImagePoint {
    pub x: f64,
    pub y: f64,
}
