//! Pinhole intrinsics of the depth camera, in pixels: derived from the camera settings
//! (image size, horizontal field of view, optional explicit focal lengths and principal
//! point) and used by the camera to turn pixels into rays.

/// Pinhole intrinsics in pixels.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CameraIntrinsics {
    /// Image width (columns).
    pub width: usize,
    /// Image height (rows).
    pub height: usize,
    /// Focal length along x, px.
    pub fx: f64,
    /// Focal length along y, px.
    pub fy: f64,
    /// Principal point x, px.
    pub cx: f64,
    /// Principal point y, px.
    pub cy: f64,
}

impl CameraIntrinsics {
    /// Square pixels, principal point at the image centre, horizontal field of view `hfov`
    /// (rad).
    pub fn from_hfov(width: usize, height: usize, hfov: f64) -> Self {
        let fx = 0.5 * width as f64 / (0.5 * hfov).tan();
        Self {
            width,
            height,
            fx,
            fy: fx,
            cx: 0.5 * width as f64,
            cy: 0.5 * height as f64,
        }
    }
}
