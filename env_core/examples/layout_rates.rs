//! How hard a layout config is for the generator: over a range of seeds, the share of seeds
//! that get a layout within `max_attempts`, the attempts a layout takes (mean and worst) and
//! the time per layout (the visibility measurements below excluded); and the smallest
//! silhouette of a hidden jar (target or decoy) in the camera's image, which shows whether
//! the camera still frames the hidden jars (a jar outside the image is hidden trivially).
//!
//! `cargo run --release -p env_core --example layout_rates -- [seeds] [key=value ...]`
//!
//! `seeds` is the number of seeds (0.., default 2000); each `key=value` sets one scene
//! setting, numbers separated by commas for a pair (`jar_count=8,12`, `cupboard_width=0.8`,
//! `hidden_decoys=1`, `target_shape=square`).

use std::time::Instant;

use env_core::scene::config::MAX_JARS;
use env_core::scene::{target_visibility, Cupboard, DepthCamera, Layout, SceneConfig};
use env_core::settings::{Checked, SettingValue, Settings};

/// `value` as a setting value: an int, a float, a comma-separated list of them, or text.
fn parse_value(value: &str) -> SettingValue {
    if value.contains(',') {
        return SettingValue::List(value.split(',').map(parse_value).collect());
    }
    if let Ok(v) = value.parse::<i64>() {
        SettingValue::Int(v)
    } else if let Ok(v) = value.parse::<f64>() {
        SettingValue::Float(v)
    } else {
        SettingValue::Text(value.to_owned())
    }
}

fn main() {
    let mut seeds = 2000u64;
    let mut pairs = Vec::new();
    for arg in std::env::args().skip(1) {
        match arg.split_once('=') {
            Some((key, value)) => pairs.push((key.to_owned(), parse_value(value))),
            None => seeds = arg.parse().expect("the number of seeds"),
        }
    }
    let config: Checked<SceneConfig> =
        SceneConfig::from_pairs(pairs.iter().map(|(k, v)| (k.as_str(), v.clone())))
            .unwrap_or_else(|e| panic!("{e}"));
    let cupboard = Cupboard::new(&config.cupboard);
    let camera = DepthCamera::new(&config.camera).expect("camera");
    let (mut found, mut attempts, mut worst) = (0u64, 0usize, 0usize);
    let mut jars = [0u64; MAX_JARS + 1];
    let (mut smallest, mut small) = (usize::MAX, 0u64);
    let mut elapsed = 0.0;
    for seed in 0..seeds {
        let start = Instant::now();
        let (layout, tries) = Layout::generate_counted(&config.layout, &cupboard, &camera, seed);
        elapsed += start.elapsed().as_secs_f64();
        attempts += tries;
        worst = worst.max(tries);
        if let Ok(layout) = layout {
            found += 1;
            jars[layout.jars.len()] += 1;
            let silhouette = std::iter::once(layout.target)
                .chain(layout.decoys.iter().copied())
                .map(|i| target_visibility(&camera, &cupboard, &layout.jars, i).silhouette_pixels)
                .min()
                .expect("a target");
            smallest = smallest.min(silhouette);
            small += u64::from(silhouette < 20);
        }
    }
    let settings: Vec<String> = pairs.iter().map(|(k, v)| format!("{k}={v}")).collect();
    println!("settings: {}", settings.join(" "));
    println!(
        "{found}/{seeds} seeds found a layout ({:.2} %); attempts mean {:.1}, worst {worst}; \
         {:.2} ms per seed",
        100.0 * found as f64 / seeds as f64,
        attempts as f64 / seeds as f64,
        1e3 * elapsed / seeds as f64,
    );
    let counts: Vec<String> = jars
        .iter()
        .enumerate()
        .filter(|(_, &c)| c > 0)
        .map(|(n, c)| format!("{n}: {c}"))
        .collect();
    println!("jar counts {{{}}}", counts.join(", "));
    println!(
        "smallest silhouette of a hidden jar {smallest} px; layouts with one under 20 px: {small}"
    );
}
