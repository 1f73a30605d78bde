//! The GPIS prior from the depth camera's first look (design notes §3, paper §IV.A):
//! surface points (f = 0), optional free-space points in front of them along their camera
//! rays (f = +offset), and the optional circle prior behind each cluster of depth points.

use super::config::MapConfig;
use crate::gpis::{GpisError, GridSpec, Observation};
use crate::scene::point_cloud::thin_indices;

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

/// The prior's observations from the noisy depth slice seen from `camera` (x, y). Points
/// outside the map's bounds (noise can push wall points out) are left out, the rest thinned
/// evenly to `max_prior_depth_points`.
pub fn depth_prior(
    slice: &[[f64; 2]],
    camera: [f64; 2],
    grid: &GridSpec,
    config: &MapConfig,
) -> Result<Vec<Observation>, GpisError> {
    let depth_var = config.depth_noise_std.powi(2);
    let seen: Vec<[f64; 2]> = slice
        .iter()
        .copied()
        .filter(|&p| grid.contains(p))
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
    Ok(observations)
}
