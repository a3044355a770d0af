//! Pixel noise (spec §3.2): leak events as Poisson events at the per-pixel rate
//! `r_leak·10^(spread·N(0,1))` (drawn once per camera) rather than as a drift of L_ref — over a
//! 4.5 s trial a static pixel's drift yields at most one leak event, at the same mean rate —
//! and shot noise, Poisson at `r_shot`, half ON, half OFF. Events of background pixels go
//! straight to the output; those of patch pixels are queued per pixel for the DVS model, which
//! resets the pixel at each (v2e: L_ref ← L̃). Hot pixels are not modelled.

use super::PixelModel;
use super::event::{NOISE_LABEL, RawEvent};
use crate::sim::camera::Camera;
use neurotac_core::time::{s_to_us, us_to_s};
use rand::RngExt;
use rand_chacha::ChaCha8Rng;

impl PixelModel {
    /// Draws the noise of every pixel over `[0, duration_s)`: events of background pixels go
    /// straight to `out`, those of patch pixels into the per-pixel queues.
    pub(super) fn draw_noise(
        &mut self,
        camera: &Camera,
        duration_s: f64,
        rng: &mut ChaCha8Rng,
        out: &mut Vec<RawEvent>,
    ) {
        let shot = self.params.noise.shot_rate_hz;
        let t_ref = self.params.pixel.refractory_s;
        let width = camera.width as usize;
        self.noise_t.clear();
        self.noise_on.clear();
        let mut pending = std::mem::take(&mut self.pending_noise);
        let mut times = std::mem::take(&mut self.pixel_noise);
        pending.clear();
        for (pixel, &leak) in camera.leak_rate_hz.iter().enumerate() {
            let rate = leak as f64 + shot;
            if rate <= 0.0 {
                continue;
            }
            times.clear();
            let mut t = 0.0;
            loop {
                t += -(1.0 - rng.random::<f64>()).ln() / rate;
                if t >= duration_s {
                    break;
                }
                // ON for leak, or for half of the shot noise.
                let u = rng.random::<f64>() * rate;
                let on = u < leak as f64 + 0.5 * shot;
                // Whole µs; a pixel in reset after its previous event cannot fire.
                let t = us_to_s(s_to_us(t));
                if times
                    .last()
                    .is_none_or(|&(last, _)| t - last >= t_ref - 1e-9)
                {
                    times.push((t, on));
                }
            }
            if times.is_empty() {
                continue;
            }
            let patch_index = self.patches.index_of[pixel];
            if patch_index == u32::MAX {
                let (x, y) = ((pixel % width) as u16, (pixel / width) as u16);
                out.extend(times.iter().map(|&(t, on)| RawEvent {
                    t_us: s_to_us(t),
                    y,
                    x,
                    on,
                    label: NOISE_LABEL,
                }));
            } else {
                pending.extend(times.iter().map(|&(t, on)| (patch_index as usize, t, on)));
            }
        }
        // CSR by patch pixel (pending is in image order, so sort by patch index, stable in time).
        pending.sort_by_key(|&(j, _, _)| j);
        self.noise_offsets.fill(0);
        for &(j, _, _) in &pending {
            self.noise_offsets[j + 1] += 1;
        }
        for j in 0..self.noise_offsets.len() - 1 {
            self.noise_offsets[j + 1] += self.noise_offsets[j];
        }
        for &(_, t, on) in &pending {
            self.noise_t.push(t);
            self.noise_on.push(on);
        }
        self.pending_noise = pending;
        self.pixel_noise = times;
        for j in 0..self.next_noise.len() {
            let start = self.noise_offsets[j];
            self.noise_cursor[j] = start;
            self.next_noise[j] = if start < self.noise_offsets[j + 1] {
                self.noise_t[start as usize]
            } else {
                f64::INFINITY
            };
        }
    }

    pub(super) fn advance_noise(&mut self, j: usize) {
        let c = self.noise_cursor[j] + 1;
        self.noise_cursor[j] = c;
        self.next_noise[j] = if c < self.noise_offsets[j + 1] {
            self.noise_t[c as usize]
        } else {
            f64::INFINITY
        };
    }
}
