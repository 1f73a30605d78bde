//! The GPIS prior from the depth camera's first look (`docs/DESIGN.md` §3, paper §IV.A):
//! surface points (f = 0), optional free-space points in front of them along their camera
//! rays (f = +offset), and the optional circle prior behind each cluster of depth points.
//!
//! This is the one implementation of the prior: the environment starts its map with
//! [`depth_prior`], and the bindings expose it so that the paper's
//! experiments and the demo get the identical rows for the same slice and settings. The
//! paper's prior options are settings: a constant mean is [`MapConfig::prior_mean`] (on the
//! map, not in the rows), the circle prior [`MapConfig::circle_prior_diameter`], free space
//! [`MapConfig::free_space_offset`], leaving out the walls' points
//! [`MapConfig::wall_clearance`].

use crate::episode::error::EpisodeError;
use crate::episode::maps::MapConfig;
use crate::gpis::{GridSpec, Observation};
use crate::scene::point_cloud::thin_indices;
use crate::settings::SettingError;

/// Depth points closer than this belong to the same cluster (one visible jar face), m.
const CLUSTER_GAP: f64 = 0.015;
/// Clusters with fewer points get no circle prior.
const MIN_CLUSTER_POINTS: usize = 3;

fn unit(v: [f64; 2]) -> [f64; 2] {
    let length = v[0].hypot(v[1]);
    [v[0] / length, v[1] / length]
}

/// Groups points by single linkage at [`CLUSTER_GAP`]. Cost O(n²) for n points (n ≤ a few
/// hundred after thinning).
fn clusters(points: &[[f64; 2]]) -> Vec<Vec<usize>> {
    let mut label: Vec<Option<usize>> = vec![None; points.len()];
    let mut groups = Vec::new();
    for seed in 0..points.len() {
        if label[seed].is_some() {
            continue;
        }
        let id = groups.len();
        let mut members = vec![seed];
        label[seed] = Some(id);
        let mut next = 0;
        while next < members.len() {
            let p = points[members[next]];
            next += 1;
            for (q, slot) in label.iter_mut().enumerate() {
                if slot.is_none() && (points[q][0] - p[0]).hypot(points[q][1] - p[1]) < CLUSTER_GAP
                {
                    *slot = Some(id);
                    members.push(q);
                }
            }
        }
        groups.push(members);
    }
    groups
}

/// The prior's observations, in the order they enter the map, from the noisy depth
/// `slice` seen from `camera` (x, y). Points outside the map's bounds (noise can push wall
/// points out) or within `config.wall_clearance` of its side and back walls are left out,
/// the rest thinned evenly to `max_prior_depth_points`; then come the free-space points
/// and the circle priors (a circle that does not fit in the bounds is dropped). The list is
/// cut so that it holds at most `max_rows / 2` GP rows: the rest is room for touch.
/// `config` must be valid ([`crate::episode::EpisodeConfig::validate`]); fails on a non-finite
/// camera. Cost O(p + n²) for p slice points and n kept points.
pub fn depth_prior(
    slice: &[[f64; 2]],
    camera: [f64; 2],
    grid: &GridSpec,
    config: &MapConfig,
) -> Result<Vec<Observation>, EpisodeError> {
    if let Some(&value) = camera.iter().find(|v| !v.is_finite()) {
        return Err(SettingError::out_of_range("camera", "a finite (x, y)", value).into());
    }
    let depth_var = config.depth_noise_std.powi(2);
    let [[x0, x1], [_, y1]] = grid.bounds();
    let clearance = config.wall_clearance;
    let clear_of_walls =
        |p: [f64; 2]| p[0] - x0 >= clearance && x1 - p[0] >= clearance && y1 - p[1] >= clearance;
    let seen: Vec<[f64; 2]> = slice
        .iter()
        .copied()
        .filter(|&p| grid.contains(p) && clear_of_walls(p))
        .collect();
    let inside: Vec<[f64; 2]> = thin_indices(seen.len(), config.max_prior_depth_points)
        .into_iter()
        .map(|i| seen[i])
        .collect();
    let mut observations = Vec::with_capacity(2 * inside.len());
    for (i, &p) in inside.iter().enumerate() {
        observations.push(Observation::value(i, p, 0.0, depth_var)?);
    }
    if let Some(offset) = config.free_space_offset {
        for (i, &p) in inside.iter().enumerate() {
            let towards_camera = unit([camera[0] - p[0], camera[1] - p[1]]);
            let q = [
                p[0] + offset * towards_camera[0],
                p[1] + offset * towards_camera[1],
            ];
            if grid.contains(q) {
                observations.push(Observation::value(i, q, offset, depth_var)?);
            }
        }
    }
    if let Some(diameter) = config.circle_prior_diameter {
        let contact_var = config.contact_noise_std.powi(2);
        let normal_var = config.normal_noise_std.powi(2);
        for members in clusters(&inside) {
            if members.len() < MIN_CLUSTER_POINTS {
                continue;
            }
            let n = members.len() as f64;
            let centroid = members.iter().fold([0.0, 0.0], |acc, &m| {
                [acc[0] + inside[m][0] / n, acc[1] + inside[m][1] / n]
            });
            // The visible face is the front of the object: its centre lies behind it.
            let away = unit([centroid[0] - camera[0], centroid[1] - camera[1]]);
            let radius = diameter / 2.0;
            let centre = [
                centroid[0] + radius * away[0],
                centroid[1] + radius * away[1],
            ];
            let circle = Observation::circle_prior(centre, diameter, contact_var, normal_var)?;
            if circle.iter().all(|o| grid.contains(o.point())) {
                observations.extend(circle);
            }
        }
    }
    // Keep room for touch: the prior takes at most half the rows.
    let budget = config.max_rows / 2;
    let mut rows = 0;
    let fit = observations
        .iter()
        .take_while(|o| {
            rows += o.n_rows();
            rows <= budget
        })
        .count();
    observations.truncate(fit);
    Ok(observations)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn grid() -> GridSpec {
        GridSpec::new([[-0.3, 0.3], [0.0, 0.3]], (40, 80)).unwrap()
    }

    /// A jar's front face (10 points) and a stretch of the back wall (10 points).
    fn slice() -> Vec<[f64; 2]> {
        let face = (0..10).map(|k| [-0.02 + 0.004 * k as f64, 0.1]);
        let wall = (0..10).map(|k| [0.1 + 0.004 * k as f64, 0.299]);
        face.chain(wall).collect()
    }

    #[test]
    fn wall_clearance_leaves_out_the_walls_and_nothing_else() {
        let config = MapConfig {
            free_space_offset: None,
            ..MapConfig::default()
        };
        let all = depth_prior(&slice(), [0.0, -0.25], &grid(), &config).unwrap();
        assert_eq!(all.len(), 20);
        let config = MapConfig {
            wall_clearance: 0.005,
            ..config
        };
        let clear = depth_prior(&slice(), [0.0, -0.25], &grid(), &config).unwrap();
        assert_eq!(clear.len(), 10);
        assert!(clear.iter().all(|o| o.point()[1] < 0.2));
    }

    #[test]
    fn circle_priors_sit_behind_their_cluster_and_only_where_they_fit() {
        let config = MapConfig {
            free_space_offset: None,
            circle_prior_diameter: Some(0.03),
            ..MapConfig::default()
        };
        let rows = depth_prior(&slice(), [0.0, -0.25], &grid(), &config).unwrap();
        // Two clusters; the one on the back wall would put its circle beyond the wall.
        let contacts: Vec<_> = rows
            .iter()
            .filter(|o| matches!(o, Observation::Contact { .. }))
            .collect();
        assert_eq!(contacts.len(), 4);
        // Its centre lies one radius behind the face (y = 0.1), seen from the camera.
        let centre_y = contacts.iter().map(|o| o.point()[1]).sum::<f64>() / 4.0;
        assert!((centre_y - 0.115).abs() < 1e-4, "{centre_y}");
    }

    #[test]
    fn the_prior_leaves_half_the_rows_for_touch() {
        let config = MapConfig {
            max_rows: 24,
            ..MapConfig::default()
        };
        let rows = depth_prior(&slice(), [0.0, -0.25], &grid(), &config).unwrap();
        assert_eq!(rows.iter().map(Observation::n_rows).sum::<usize>(), 12);
    }

    #[test]
    fn bad_cameras_are_errors_not_panics() {
        let config = MapConfig::default();
        assert!(depth_prior(&slice(), [f64::INFINITY, -0.25], &grid(), &config).is_err());
    }
}
