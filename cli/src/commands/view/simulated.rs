//! `neurotac view --simulate TEXTURE`: the bundled simulator's slides over one texture, one
//! after another, as a [`StreamSource`].
//!
//! Slide `i` is simulated with the camera (and rig) of the seed's datasets and the trial seed
//! of trial `FIRST_VIEW_TRIAL + i` of the texture's class: slides no dataset of that seed
//! holds (datasets have far fewer trials), so a recogniser trained on one is shown slides it
//! has not seen.

use neurotac_core::EventBuffer;
use neurotac_experiments::datasets::simulated::{TextureSet, camera_seed, trial_seed};
use neurotac_sensor::sim::{Camera, PreparedTexture, SimParams, Simulator, Texture};
use neurotac_view::{SourceError, SourceRead, StreamSource};

/// Trial index of the first viewed slide (see the module docs).
pub const FIRST_VIEW_TRIAL: usize = 1_000_000;

/// Events handed over per read (as a file reader's chunk).
const CHUNK: usize = 4096;

/// Simulated slides over one texture (module docs).
pub struct SimulatedSlides {
    simulator: Simulator,
    texture: PreparedTexture,
    set: TextureSet,
    class: usize,
    seed: u64,
    slide: usize,
    events: EventBuffer,
    next: usize,
}

impl SimulatedSlides {
    /// Slides over the texture called `name` (in either bundled set), with `params`, the
    /// camera and trial seeds of `seed`; simulates the first slide.
    pub fn new(name: &str, params: SimParams, seed: u64) -> anyhow::Result<Self> {
        let texture = Texture::from_name(name)?;
        let found = [TextureSet::Artificial, TextureSet::Natural]
            .into_iter()
            .find_map(|set| {
                let class = set
                    .class_names()
                    .iter()
                    .position(|c| *c == texture.name())?;
                Some((set, class))
            });
        let Some((set, class)) = found else {
            anyhow::bail!(
                "--simulate {name:?}: not a texture of the bundled sets (artificial: {}; natural: {})",
                TextureSet::Artificial.class_names().join(", "),
                TextureSet::Natural.class_names().join(", ")
            );
        };
        let camera = Camera::new(&params, camera_seed(seed));
        let simulator = Simulator::new(params, &camera)?;
        let texture = simulator.prepare(texture);
        let mut slides = Self {
            simulator,
            texture,
            set,
            class,
            seed,
            slide: 0,
            events: EventBuffer::new(),
            next: 0,
        };
        slides.simulate();
        Ok(slides)
    }

    fn simulate(&mut self) {
        let trial = trial_seed(
            self.seed,
            self.set,
            self.class,
            FIRST_VIEW_TRIAL + self.slide,
        );
        self.events = self
            .simulator
            .simulate_slide(&self.texture, self.slide, trial)
            .events;
        self.next = 0;
    }
}

impl StreamSource for SimulatedSlides {
    fn label(&self) -> String {
        format!(
            "simulated {}, slide {} (seed {})",
            self.texture.texture.name(),
            self.slide + 1,
            self.seed
        )
    }

    fn read(&mut self, chunk: &mut EventBuffer) -> Result<SourceRead, SourceError> {
        let end = (self.next + CHUNK).min(self.events.len());
        if self.next == end {
            return Ok(SourceRead::End);
        }
        for i in self.next..end {
            chunk.push(self.events.get(i).expect("in range"));
        }
        self.next = end;
        Ok(SourceRead::Events)
    }

    fn is_live(&self) -> bool {
        false
    }

    fn rewind(&mut self) -> Result<(), SourceError> {
        self.next = 0;
        Ok(())
    }

    fn next_stream(&mut self) -> Result<bool, SourceError> {
        self.slide += 1;
        self.simulate();
        Ok(true)
    }
}
