use neurotac_sensor::sim::*;
use std::time::Instant;
fn main() {
    let args: Vec<String> = std::env::args().collect();
    let lever: f64 = args.get(1).map(|s| s.parse().unwrap()).unwrap_or(0.42);
    let trials: u64 = args.get(2).map(|s| s.parse().unwrap()).unwrap_or(2);
    let names: Vec<String> = if args.len() > 3 { args[3..].to_vec() } else { GRID_SIZES_MM.iter().map(|d| format!("{d}")).collect() };
    let mut p = SimParams::default();
    p.contact.lever_mm = lever;
    let cam = Camera::new(&p, 1);
    let mut sim = Simulator::new(p, &cam).unwrap();
    for name in names {
        let tex = sim.prepare(Texture::from_name(&name).unwrap());
        let mut tot = 0.0; let mut ev = 0; let mut noise = 0; let mut wall = 0.0; let mut psteps = 0; let mut maxd: f64 = 0.0; let mut kept=0;
        for k in 0..trials {
            let t0 = Instant::now();
            let tr = sim.simulate(&tex, 1000 + k);
            wall += t0.elapsed().as_secs_f64();
            let s = taxel_spikes(&tr).unwrap();
            tot += s.spikes.total_spikes() as f64 / 49.0;
            ev += tr.events.len(); noise += tr.noise_count(); psteps += tr.info.pixel_stats.pixel_steps;
            maxd = maxd.max(tr.info.max_displacement_px);
            kept += s.counts.after_filters;
        }
        let n = trials as f64;
        println!("{name:>20}: {:6.2} spikes/taxel  events {:7.0} (noise {:6.0}) kept {:6.0} pixsteps {:9.0} maxdisp {:5.2} px  {:.3} s/trial", tot/n, ev as f64/n, noise as f64/n, kept as f64/n, psteps as f64/n, maxd, wall/n);
    }
}
