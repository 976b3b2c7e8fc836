//! Where a ground site can be: eq. 52 visibility of the vehicle during the whole entry, the
//! visible lattice of candidate sites and the search box around the feasible set.

use super::problem::GroundProblem;
use super::site::Site;
use crate::error::OptimizerError;
use entrynav::beacons::ground_visibility_margin;
use entrynav::frames::position_to_spherical;
use entrynav::math::norm;
use std::f64::consts::FRAC_PI_2;
use std::f64::consts::PI;

impl GroundProblem {
    /// Smallest elevation \[rad\] of the vehicle above the local horizon of `site` over the
    /// trajectory (> 0: visible during the whole entry by eq. 52).
    pub fn min_elevation_of(&self, site: &Site) -> f64 {
        let b = site.fixed_position(self.trajectory.planet.radius);
        self.fixed
            .iter()
            .map(|v| ground_visibility_margin(&b, v))
            .fold(f64::INFINITY, f64::min)
    }

    /// Largest elevation \[rad\] of the vehicle above the local horizon of `site` over the
    /// trajectory.
    pub fn max_elevation_of(&self, site: &Site) -> f64 {
        let b = site.fixed_position(self.trajectory.planet.radius);
        self.fixed
            .iter()
            .map(|v| ground_visibility_margin(&b, v))
            .fold(f64::NEG_INFINITY, f64::max)
    }

    /// How far \[rad\] `site` falls short of the visibility requirement (0: feasible): eq. 52's
    /// minimum elevation during the whole entry, or with partial visibility the elevation mask
    /// at the site's best sample (a margin of 1e-9 rad keeps answers strictly inside).
    pub fn visibility_shortfall(&self, site: &Site) -> f64 {
        if self.whole_entry {
            (self.min_elevation + 1e-9 - self.min_elevation_of(site)).max(0.0)
        } else {
            (self.elevation_mask + 1e-9 - self.max_elevation_of(site)).max(0.0)
        }
    }

    /// Whether `site` meets the visibility requirement ([`Self::visibility_shortfall`] is 0).
    pub fn is_feasible(&self, site: &Site) -> bool {
        self.visibility_shortfall(site) == 0.0
    }

    /// With partial visibility, the search box: every sample's ground point widened by the
    /// ground angle at which the vehicle sits on the elevation mask,
    /// θ = arccos(R_b cos e / r) − e, the box of their union widened by one degree.
    fn partial_bounds(&self) -> (Vec<f64>, Vec<f64>) {
        let r_b = self.trajectory.planet.radius + self.altitude_m;
        let e = self.elevation_mask;
        let (mut lat_lo, mut lat_hi) = (f64::INFINITY, f64::NEG_INFINITY);
        let (mut lon_lo, mut lon_hi) = (f64::INFINITY, f64::NEG_INFINITY);
        let lon_ref = position_to_spherical(&self.fixed[0]).1;
        for v in &self.fixed {
            let (r, lon, lat) = position_to_spherical(v);
            let theta = ((r_b * e.cos() / r).clamp(-1.0, 1.0).acos() - e).max(0.0);
            // Longitude unwrapped around the first sample's.
            let lon = lon_ref + (lon - lon_ref + PI).rem_euclid(2.0 * PI) - PI;
            let half_lon = (theta / lat.cos().max(1e-3)).min(PI);
            lat_lo = lat_lo.min(lat - theta);
            lat_hi = lat_hi.max(lat + theta);
            lon_lo = lon_lo.min(lon - half_lon);
            lon_hi = lon_hi.max(lon + half_lon);
        }
        let pad = 1f64.to_radians();
        let (lat_lo, lat_hi) = (
            (lat_lo - pad).max(-FRAC_PI_2),
            (lat_hi + pad).min(FRAC_PI_2),
        );
        let (lon_lo, lon_hi) = (lon_lo - pad, lon_hi + pad);
        let lower = (0..self.count).flat_map(|_| [lat_lo, lon_lo]).collect();
        let upper = (0..self.count).flat_map(|_| [lat_hi, lon_hi]).collect();
        (lower, upper)
    }

    /// Latitude/longitude of the centre of the smallest visibility cap (below the trajectory's
    /// lowest sample) and the cap's angular radius \[rad\].
    fn smallest_cap(&self) -> (f64, f64, f64) {
        let r_b = self.trajectory.planet.radius + self.altitude_m;
        let (mut best, mut theta) = (0, f64::INFINITY);
        for (k, v) in self.fixed.iter().enumerate() {
            let t = (r_b / norm(v)).clamp(-1.0, 1.0).acos();
            if t < theta {
                (best, theta) = (k, t);
            }
        }
        let (_, lon, lat) = position_to_spherical(&self.fixed[best]);
        (lat, lon, theta)
    }

    /// Feasible sites on the lattice of multiples of `grid_deg` degrees in latitude and
    /// longitude (longitude in (−180°, 180°]). Errors when no lattice point is feasible.
    pub fn visible_grid(&self, grid_deg: f64) -> Result<Vec<Site>, OptimizerError> {
        if !(grid_deg.is_finite() && grid_deg > 0.0 && grid_deg <= 30.0) {
            return Err(OptimizerError::InvalidInput(format!(
                "grid spacing {grid_deg} deg must be in (0, 30]"
            )));
        }
        let (lat_c, lon_c, theta) = self.smallest_cap();
        let step = grid_deg.to_radians();
        let lat_lo = ((lat_c - theta) / step).floor() as i64;
        let lat_hi = ((lat_c + theta) / step).ceil() as i64;
        let mut out = Vec::new();
        for i in lat_lo..=lat_hi {
            let lat = i as f64 * step;
            if lat.abs() > FRAC_PI_2 {
                continue;
            }
            let cos_lat = lat.cos().max(1e-6);
            let half = (theta / cos_lat).min(PI);
            let lon_lo = ((lon_c - half) / step).floor() as i64;
            let lon_hi = ((lon_c + half) / step).ceil() as i64;
            for j in lon_lo..=lon_hi {
                let site = Site {
                    lat,
                    lon: j as f64 * step,
                    altitude_m: self.altitude_m,
                }
                .canonical();
                if self.is_feasible(&site) && !out.iter().any(|s: &Site| same_site(s, &site)) {
                    out.push(site);
                }
            }
        }
        if out.is_empty() {
            return Err(self.no_site_error());
        }
        Ok(out)
    }

    pub(super) fn no_site_error(&self) -> OptimizerError {
        if !self.whole_entry {
            return OptimizerError::Infeasible(format!(
                "no site of scenario '{}' sees the vehicle above a {:.3} deg elevation mask at \
                 any time of the entry",
                self.scenario.config.name,
                self.elevation_mask.to_degrees()
            ));
        }
        OptimizerError::Infeasible(format!(
            "no site is visible during the whole entry of scenario '{}' with a minimum elevation \
             of {:.3} deg (eq. 52: the vehicle must stay above every beacon's horizon from t = 0 \
             to t = {} s)",
            self.scenario.config.name,
            self.min_elevation.to_degrees(),
            self.trajectory.times.last().copied().unwrap_or(0.0)
        ))
    }

    /// Search box `[lat, lon]` per site (radians, longitude unwrapped around the smallest cap):
    /// the bounding box of the feasible points of a fine lattice, widened by one cell.
    pub fn bounds(&self) -> Result<(Vec<f64>, Vec<f64>), OptimizerError> {
        if !self.whole_entry {
            return Ok(self.partial_bounds());
        }
        let (lat_c, lon_c, theta) = self.smallest_cap();
        let n = 80;
        let cell = 2.0 * theta / n as f64;
        let (mut lat_lo, mut lat_hi) = (f64::INFINITY, f64::NEG_INFINITY);
        let (mut lon_lo, mut lon_hi) = (f64::INFINITY, f64::NEG_INFINITY);
        let cos_lat = lat_c.cos().max(1e-3);
        let lon_cell = (cell / cos_lat).min(PI / n as f64);
        for i in 0..=n {
            let lat = lat_c - theta + i as f64 * cell;
            for j in 0..=n {
                let lon = lon_c + (j as f64 - n as f64 / 2.0) * lon_cell;
                let site = Site {
                    lat,
                    lon,
                    altitude_m: self.altitude_m,
                };
                if lat.abs() <= FRAC_PI_2 && self.is_feasible(&site) {
                    lat_lo = lat_lo.min(lat);
                    lat_hi = lat_hi.max(lat);
                    lon_lo = lon_lo.min(lon);
                    lon_hi = lon_hi.max(lon);
                }
            }
        }
        if !lat_lo.is_finite() {
            return Err(self.no_site_error());
        }
        let (lat_lo, lat_hi) = (
            (lat_lo - cell).max(-FRAC_PI_2),
            (lat_hi + cell).min(FRAC_PI_2),
        );
        let (lon_lo, lon_hi) = (lon_lo - lon_cell, lon_hi + lon_cell);
        let lower = (0..self.count).flat_map(|_| [lat_lo, lon_lo]).collect();
        let upper = (0..self.count).flat_map(|_| [lat_hi, lon_hi]).collect();
        Ok((lower, upper))
    }

    /// Sites from the search vector `[lat₁, lon₁, lat₂, …]` (radians).
    pub fn sites_from(&self, x: &[f64]) -> Vec<Site> {
        x.chunks_exact(2)
            .map(|c| Site {
                lat: c[0],
                lon: c[1],
                altitude_m: self.altitude_m,
            })
            .collect()
    }
}

/// Two sites at the same latitude and longitude (to 1e-12 rad).
fn same_site(a: &Site, b: &Site) -> bool {
    (a.lat - b.lat).abs() < 1e-12 && (a.lon - b.lon).abs() < 1e-12
}
