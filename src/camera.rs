//! A pinhole camera: one primary ray through each pixel centre (ALGORITHM.md §2 [ours]).

use glam::Vec3;

/// A perspective camera looking from `position` at `target`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Camera {
    pub position: Vec3,
    pub target: Vec3,
    pub up: Vec3,
    /// Vertical field of view, degrees.
    pub vfov_deg: f32,
    pub width: u32,
    pub height: u32,
    // Orthonormal frame and scale, derived once.
    forward: Vec3,
    right: Vec3,
    true_up: Vec3,
    tan_half: f32,
    aspect: f32,
}

impl Camera {
    /// A camera for a `width`×`height` image. `up` need not be orthogonal to the view direction,
    /// only not parallel to it (a parallel `up` falls back to +Z, then +X).
    pub fn look_at(
        position: Vec3,
        target: Vec3,
        up: Vec3,
        vfov_deg: f32,
        width: u32,
        height: u32,
    ) -> Camera {
        let forward = (target - position).normalize_or(Vec3::NEG_Z);
        let mut right = forward.cross(up);
        if right.length_squared() < 1e-12 {
            right = forward.cross(Vec3::Z);
            if right.length_squared() < 1e-12 {
                right = forward.cross(Vec3::X);
            }
        }
        let right = right.normalize();
        let true_up = right.cross(forward);
        Camera {
            position,
            target,
            up,
            vfov_deg,
            width,
            height,
            forward,
            right,
            true_up,
            tan_half: libm::tanf(vfov_deg.to_radians() * 0.5),
            aspect: width as f32 / height.max(1) as f32,
        }
    }

    /// Unit direction of the primary ray through the centre of pixel (x, y); y = 0 is the top row.
    #[inline]
    pub fn ray_dir(&self, x: u32, y: u32) -> Vec3 {
        self.ray_dir_at(x, y, 0.0, 0.0)
    }

    /// Unit direction of the primary ray through the point `(dx, dy)` pixels from the centre of
    /// pixel (x, y) (x to the right, y down). With a zero offset, the very bits of
    /// [`ray_dir`](Self::ray_dir): adding +0.0 to the centre changes nothing.
    #[inline]
    pub fn ray_dir_at(&self, x: u32, y: u32, dx: f32, dy: f32) -> Vec3 {
        let sx =
            ((x as f32 + 0.5 + dx) / self.width as f32 * 2.0 - 1.0) * self.tan_half * self.aspect;
        let sy = (1.0 - (y as f32 + 0.5 + dy) / self.height as f32 * 2.0) * self.tan_half;
        (self.forward + self.right * sx + self.true_up * sy).normalize()
    }

    /// The angle, radians, one pixel spans at the eye around the unit ray direction `dir`:
    /// the pixel spacing on the image plane at distance 1 (`2·tan(vfov/2) / height`; pixels
    /// are square) times `cos α`, α the angle between `dir` and the view direction. Off-centre
    /// a pixel spans that across the line to the image centre and `cos² α` along it; this is
    /// the larger of the two, for an isotropic texture filter that must not alias.
    #[inline]
    pub fn pixel_angle(&self, dir: Vec3) -> f32 {
        2.0 * self.tan_half / self.height.max(1) as f32 * dir.dot(self.forward)
    }

    /// Continuous pixel coordinates (x, y) at which world point `p` appears, or `None` behind
    /// the camera. Pixel (i, j)'s centre is at (i + 0.5, j + 0.5).
    pub fn project(&self, p: Vec3) -> Option<(f32, f32)> {
        let d = p - self.position;
        let z = d.dot(self.forward);
        if z <= 0.0 {
            return None;
        }
        let sx = d.dot(self.right) / (z * self.tan_half * self.aspect);
        let sy = d.dot(self.true_up) / (z * self.tan_half);
        Some((
            (sx + 1.0) * 0.5 * self.width as f32,
            (1.0 - sy) * 0.5 * self.height as f32,
        ))
    }

    /// Unit view direction.
    pub fn forward(&self) -> Vec3 {
        self.forward
    }

    /// OpenEXR's `worldToCamera` and `worldToNDC` attributes for this camera, as OpenEXR
    /// stores an M44f: a matrix applied to row vectors on its left (`p' = p·M`), flattened row
    /// by row. Camera space is OpenEXR's: left-handed, x to the right of the image, y up, z
    /// along the view (points in front have z > 0), origin at the eye. NDC is OpenEXR's too:
    /// after the division by w, (0, 0) is the top-left corner of the image and (1, 1) its
    /// bottom-right corner, so a point shows at pixel (x · width, y · height) — where
    /// [`project`](Self::project) puts it; z (here 1 / depth) is to be discarded.
    pub fn exr_matrices(&self) -> ([f32; 16], [f32; 16]) {
        use glam::{Mat4, Vec4};
        let (r, u, f, e) = (self.right, self.true_up, self.forward, self.position);
        // Column-vector matrices (glam's), whose column-major flattening is the row-vector
        // matrix flattened by rows.
        let to_camera = Mat4::from_cols(
            Vec4::new(r.x, u.x, f.x, 0.0),
            Vec4::new(r.y, u.y, f.y, 0.0),
            Vec4::new(r.z, u.z, f.z, 0.0),
            Vec4::new(-r.dot(e), -u.dot(e), -f.dot(e), 1.0),
        );
        // Camera (x, y, z) → homogeneous NDC: x_ndc·w = (x / (t·a) + z) / 2,
        // y_ndc·w = (z − y / t) / 2, z_ndc·w = 1, w = z.
        let (t, a) = (self.tan_half, self.aspect);
        let to_ndc = Mat4::from_cols(
            Vec4::new(0.5 / (t * a), 0.0, 0.0, 0.0),
            Vec4::new(0.0, -0.5 / t, 0.0, 0.0),
            Vec4::new(0.5, 0.5, 0.0, 1.0),
            Vec4::new(0.0, 0.0, 1.0, 0.0),
        );
        (
            to_camera.to_cols_array(),
            (to_ndc * to_camera).to_cols_array(),
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn centre_ray_looks_at_target_and_projection_inverts_rays() {
        let cam = Camera::look_at(Vec3::new(0.0, 1.0, 5.0), Vec3::ZERO, Vec3::Y, 40.0, 64, 48);
        // Even size: the target lies between the four centre pixels.
        let (x, y) = cam.project(Vec3::ZERO).unwrap();
        assert!((x - 32.0).abs() < 1e-3 && (y - 24.0).abs() < 1e-3);
        for (px, py) in [(0, 0), (63, 0), (10, 40), (63, 47)] {
            let p = cam.position + cam.ray_dir(px, py) * 3.0;
            let (x, y) = cam.project(p).unwrap();
            assert!((x - (px as f32 + 0.5)).abs() < 1e-3, "{x} {px}");
            assert!((y - (py as f32 + 0.5)).abs() < 1e-3, "{y} {py}");
        }
        // Top row looks up, left column looks left (−X from this viewpoint).
        assert!(cam.ray_dir(32, 0).y > cam.ray_dir(32, 47).y);
        assert!(cam.ray_dir(0, 24).x < 0.0);
        // Vertical field of view: the top edge is at half the fov from the centre.
        let top = (cam.forward() + cam.true_up * cam.tan_half).normalize();
        assert!((top.angle_between(cam.forward()).to_degrees() - 20.0).abs() < 1e-3);
        assert!(cam.project(cam.position - cam.forward()).is_none());
    }

    #[test]
    fn pixel_angle_bounds_the_spread_to_the_neighbouring_pixels() {
        let cam = Camera::look_at(
            Vec3::new(0.0, 1.0, 5.0),
            Vec3::ZERO,
            Vec3::Y,
            60.0,
            320,
            200,
        );
        for (x, y) in [
            (160, 100),
            (0, 0),
            (319, 0),
            (40, 150),
            (300, 199),
            (160, 0),
        ] {
            let d = cam.ray_dir(x, y);
            let a = cam.pixel_angle(d);
            // Unit vectors this close apart: the chord is the angle.
            let across = (cam.ray_dir(x + 1, y) - d).length();
            let down = (cam.ray_dir(x, y + 1) - d).length();
            assert!(
                across <= 1.01 * a && down <= 1.01 * a,
                "({x}, {y}): {across} {down} {a}"
            );
            if (x, y) == (160, 100) {
                assert!(
                    across >= 0.99 * a && down >= 0.99 * a,
                    "{across} {down} {a}"
                );
            }
        }
    }

    /// A point multiplied as OpenEXR does, by a row-vector matrix stored row by row.
    fn row_times(p: Vec3, m: &[f32; 16]) -> [f32; 4] {
        let v = [p.x, p.y, p.z, 1.0];
        std::array::from_fn(|c| (0..4).map(|r| v[r] * m[r * 4 + c]).sum())
    }

    #[test]
    fn exr_matrices_follow_openexrs_conventions() {
        let cam = Camera::look_at(
            Vec3::new(3.0, 2.0, 5.0),
            Vec3::new(0.0, 0.5, 0.0),
            Vec3::Y,
            35.0,
            160,
            90,
        );
        let (to_camera, to_ndc) = cam.exr_matrices();
        // The eye is the origin, the target straight ahead at its distance.
        let eye = row_times(cam.position, &to_camera);
        assert!(eye[..3].iter().all(|c| c.abs() < 1e-5), "{eye:?}");
        let t = row_times(cam.target, &to_camera);
        let dist = (cam.target - cam.position).length();
        assert!(t[0].abs() < 1e-5 && t[1].abs() < 1e-5 && (t[2] - dist).abs() < 1e-4);
        // Right and up in the image are +x and +y.
        let right = row_times(cam.position + cam.right + cam.forward, &to_camera);
        let up = row_times(cam.position + cam.true_up + cam.forward, &to_camera);
        assert!(right[0] > 0.99 && up[1] > 0.99, "{right:?} {up:?}");
        // NDC: every point lands where project() puts it, over width and height.
        for (px, py) in [(0.5, 0.5), (159.5, 0.5), (40.25, 70.75), (80.0, 45.0)] {
            let sx = (px / 160.0 * 2.0 - 1.0) * cam.tan_half * cam.aspect;
            let sy = (1.0 - py / 90.0 * 2.0) * cam.tan_half;
            let p = cam.position + (cam.forward + cam.right * sx + cam.true_up * sy) * 4.0;
            let h = row_times(p, &to_ndc);
            let (nx, ny) = (h[0] / h[3], h[1] / h[3]);
            assert!(
                (nx * 160.0 - px).abs() < 1e-3 && (ny * 90.0 - py).abs() < 1e-3,
                "pixel ({px}, {py}) -> NDC ({nx}, {ny})"
            );
        }
    }
}
