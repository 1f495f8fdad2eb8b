//! What a Unity Perception camera capture says about the eye, in ufcsr's
//! terms: the field of view from the capture's 3×3 `matrix`, and the eye's
//! pose from its `position` and `rotation`. Kept apart from the folder
//! reader ([`super::solo`]) because these are the two places where Unity's
//! conventions (column-major matrices, a left-handed Y-up world, quaternions
//! written x, y, z, w) meet ufcsr's (a centred pinhole with square pixels, a
//! right-handed Z-up world), and each conversion is tested against a known
//! answer.

use crate::format::manifest::EyePose;
use crate::optics::vector::cross;

/// Largest lens shift (projection matrix entries 0,2 and 1,2) taken as a
/// centred pinhole: Unity writes the matrix as 32-bit floats (~1e-7).
const CENTRED: f64 = 1e-4;

/// Largest difference, degrees, between the vertical field of view the
/// matrix gives and the one square pixels give.
const SQUARE_PIXELS_DEG: f64 = 1e-3;

/// The horizontal field of view, degrees, of a capture `dimension` pixels
/// (width, height) with Unity's 3×3 `matrix` (column-major, as Perception
/// writes it: `[c0.x, c0.y, c0.z, c1.x, …]`). Two forms are read:
///
/// - the top-left 3×3 of Unity's projection matrix (what Perception 1.0
///   writes; its entry 2,2 is −(far+near)/(far−near), below 0): entry 0,0
///   is 1/tan(horizontal/2), entry 1,1 is 1/tan(vertical/2);
/// - a pixel intrinsic matrix K (entry 2,2 is 1): fx, fy, cx, cy in pixels.
///
/// Refused, with the reason: any other matrix, a lens shift or skew (ufcsr's
/// eye is a centred pinhole), pixels that are not square.
pub(crate) fn horizontal_fov_deg(matrix: &[f64], [width, height]: [f64; 2]) -> Result<f64, String> {
    let &[m00, m10, _m20, m01, m11, _m21, m02, m12, m22] = matrix else {
        return Err(format!("its matrix has {} numbers, not the 9 of a 3×3 matrix", matrix.len()));
    };
    if !(matrix.iter().all(|m| m.is_finite()) && width >= 1.0 && height >= 1.0) {
        return Err("its matrix or dimension is not a set of finite numbers".into());
    }
    if m10.abs() > CENTRED || m01.abs() > CENTRED {
        return Err(format!("its matrix has skew ({m01}, {m10}): ufcsr's eye has square, unskewed pixels"));
    }
    let (horizontal, vertical) = if m22 < 0.0 {
        if m02.abs() > CENTRED || m12.abs() > CENTRED {
            return Err(format!(
                "its projection has a lens shift ({m02}, {m12}): ufcsr's eye is a centred pinhole"
            ));
        }
        (2.0 * (1.0 / m00).atan(), 2.0 * (1.0 / m11).atan())
    } else if (m22 - 1.0).abs() < 1e-6 {
        if (m02 - width / 2.0).abs() > 0.5 || (m12 - height / 2.0).abs() > 0.5 {
            return Err(format!(
                "its principal point ({m02}, {m12}) is not the image centre ({}, {}): ufcsr's eye is a centred pinhole",
                width / 2.0,
                height / 2.0
            ));
        }
        (2.0 * (width / 2.0 / m00).atan(), 2.0 * (height / 2.0 / m11).atan())
    } else {
        return Err(format!(
            "its matrix is neither a projection (entry 2,2 below 0) nor a pixel intrinsic matrix (entry 2,2 \
             equal to 1): entry 2,2 is {m22}"
        ));
    };
    let (horizontal, vertical) = (horizontal.to_degrees(), vertical.to_degrees());
    if !(horizontal > 0.0 && horizontal < 180.0 && vertical > 0.0 && vertical < 180.0) {
        return Err(format!("its matrix gives a field of view of {horizontal}° × {vertical}°"));
    }
    let square = super::metadata::vertical_fov_deg(horizontal, [width as u32, height as u32]);
    if (square - vertical).abs() > SQUARE_PIXELS_DEG {
        return Err(format!(
            "its matrix gives {horizontal:.4}° × {vertical:.4}° over {width}×{height} pixels, but square pixels \
             would give {square:.4}° vertically: ufcsr's eye has square pixels"
        ));
    }
    Ok(horizontal)
}

/// The eye's pose in ufcsr's world from a capture's Unity `position`
/// (metres) and `rotation` (a unit quaternion written x, y, z, w, as
/// Unity's `Quaternion` and Perception's output hold it). Unity's camera
/// looks along its local +Z with +X right and +Y up, in a left-handed Y-up
/// world; ufcsr's world is right-handed and Z-up, and the point (x, y, z) of
/// Unity is (x, z, y) of ufcsr (swapping two axes turns the handedness).
pub(crate) fn eye_pose(position: [f64; 3], rotation: &[f64]) -> Result<EyePose, String> {
    let &[x, y, z, w] = rotation else {
        return Err(format!("its rotation has {} numbers, not a quaternion's 4", rotation.len()));
    };
    let norm = (x * x + y * y + z * z + w * w).sqrt();
    let unit = (norm - 1.0).abs() <= 1e-3;
    if !unit || !position.iter().all(|p| p.is_finite()) {
        return Err(format!("its rotation [{x}, {y}, {z}, {w}] is not a unit quaternion (length {norm})"));
    }
    let q = [x / norm, y / norm, z / norm];
    let w = w / norm;
    let turn = |v: [f64; 3]| {
        // v + 2w (q × v) + 2 q × (q × v)
        let c = cross(q, v);
        let cc = cross(q, c);
        [0, 1, 2].map(|k| v[k] + 2.0 * w * c[k] + 2.0 * cc[k])
    };
    let to_world = |[a, b, c]: [f64; 3]| [a, c, b];
    Ok(EyePose {
        forward: to_world(turn([0.0, 0.0, 1.0])),
        position: to_world(position),
        right: to_world(turn([1.0, 0.0, 0.0])),
        up: to_world(turn([0.0, 1.0, 0.0])),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Perception's matrix of a symmetric perspective camera (column-major,
    /// near 0.3 m, far 1000 m).
    fn unity_matrix(horizontal_deg: f64, [width, height]: [f64; 2]) -> Vec<f64> {
        let m00 = 1.0 / (horizontal_deg.to_radians() / 2.0).tan();
        let m11 = m00 * width / height;
        vec![m00, 0.0, 0.0, 0.0, m11, 0.0, 0.0, 0.0, -1000.3 / 999.7]
    }

    #[test]
    fn the_projection_and_the_pixel_matrix_give_the_field_of_view_they_were_made_from() {
        let fov = horizontal_fov_deg(&unity_matrix(107.0, [640.0, 810.0]), [640.0, 810.0]).unwrap();
        assert!((fov - 107.0).abs() < 1e-9, "{fov}");
        // Rounded to 32-bit floats, as Unity writes them: within 1e-5°.
        let rounded: Vec<f64> =
            unity_matrix(107.0, [640.0, 810.0]).iter().map(|m| f64::from(*m as f32)).collect();
        assert!((horizontal_fov_deg(&rounded, [640.0, 810.0]).unwrap() - 107.0).abs() < 1e-5);
        // pysolotools' sample frame: 1024×768 with Unity's default 60° vertically → 75.169° across.
        let sample = [1.299259, 0.0, 0.0, 0.0, 1.73234534, 0.0, 0.0, 0.0, -1.0006001];
        let fov = horizontal_fov_deg(&sample, [1024.0, 768.0]).unwrap();
        assert!(
            (fov - 2.0 * (1.0f64 / 1.299259).atan().to_degrees()).abs() < 1e-12
                && (fov - 75.169).abs() < 1e-3
        );
        // K of a 90° camera 200 px wide: fx = 100.
        let k = [100.0, 0.0, 0.0, 0.0, 100.0, 0.0, 100.0, 50.0, 1.0];
        assert!((horizontal_fov_deg(&k, [200.0, 100.0]).unwrap() - 90.0).abs() < 1e-12);
    }

    #[test]
    fn shifted_skewed_stretched_and_odd_matrices_are_refused_with_the_reason() {
        let mut shifted = unity_matrix(90.0, [200.0, 100.0]);
        shifted[6] = 0.1;
        assert!(horizontal_fov_deg(&shifted, [200.0, 100.0]).unwrap_err().contains("lens shift"));
        let mut skewed = unity_matrix(90.0, [200.0, 100.0]);
        skewed[3] = 0.1;
        assert!(horizontal_fov_deg(&skewed, [200.0, 100.0]).unwrap_err().contains("skew"));
        let stretched = unity_matrix(90.0, [200.0, 150.0]);
        assert!(horizontal_fov_deg(&stretched, [200.0, 100.0]).unwrap_err().contains("square pixels"));
        let off_centre = [100.0, 0.0, 0.0, 0.0, 100.0, 0.0, 90.0, 50.0, 1.0];
        assert!(horizontal_fov_deg(&off_centre, [200.0, 100.0]).unwrap_err().contains("principal point"));
        let odd = [1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.5];
        assert!(horizontal_fov_deg(&odd, [100.0, 100.0]).unwrap_err().contains("entry 2,2 is 0.5"));
        assert!(horizontal_fov_deg(&[1.0; 4], [100.0, 100.0]).unwrap_err().contains("4 numbers"));
    }

    #[test]
    fn unity_poses_become_ufcsr_eye_poses() {
        // No rotation: Unity's +Z (forward) is ufcsr's +Y (north), +Y up is +Z.
        let pose = eye_pose([1.0, 1.7, 2.0], &[0.0, 0.0, 0.0, 1.0]).unwrap();
        assert_eq!(pose.position, [1.0, 2.0, 1.7]);
        assert_eq!((pose.forward, pose.right, pose.up), ([0.0, 1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0]));
        // 90° about Unity's +Y (a left-handed turn to the right, seen from
        // above): Unity's camera then looks along +X, its right is −Z (south).
        let half = std::f64::consts::FRAC_PI_4;
        let turned = eye_pose([0.0; 3], &[0.0, half.sin(), 0.0, half.cos()]).unwrap();
        let close = |a: [f64; 3], b: [f64; 3]| a.iter().zip(b).all(|(x, y)| (x - y).abs() < 1e-12);
        assert!(close(turned.forward, [1.0, 0.0, 0.0]), "{:?}", turned.forward);
        assert!(close(turned.right, [0.0, -1.0, 0.0]), "{:?}", turned.right);
        assert!(close(turned.up, [0.0, 0.0, 1.0]), "{:?}", turned.up);
        assert!(eye_pose([0.0; 3], &[0.0, 0.0, 0.0, 2.0]).unwrap_err().contains("not a unit quaternion"));
        assert!(eye_pose([0.0; 3], &[0.0, 0.0, 1.0]).unwrap_err().contains("3 numbers"));
    }
}
