//! Priorities into ROAM's queues (eq. 3 over a leaf, the larger of a diamond's parents'), and
//! when they are recomputed: all of a queue, only those due this frame (§7.3 deferral, with the
//! closed-form schedules that put each on the ring), those a culling-flag change touched, and
//! the end of a frame's schedules. Not here: what a frame recomputes (`../mod.rs` decides) and
//! the splits and merges that queue new elements (`mod.rs` of this folder).

use super::super::bintree::TriangleKey;
use super::super::cull;
use super::super::deferral::{BAND_MARGIN, Schedule, frames_above, frames_at_most};
use super::super::merge::{diamond_parents, primary_parent};
use super::super::priority::Wedgie;
use super::super::queues::QueueKey;
use super::super::strips;
use super::{Core, Scheduling};

impl Core<'_> {
    // ----- Priorities into the queues -----------------------------------------------------

    /// Whether new priorities of `queue` (0 split, 1 merge) are scheduled as they are computed.
    fn schedules(&self, queue: usize) -> bool {
        self.deferral.is_some() && self.scheduling[queue] == Scheduling::Scheduled
    }

    /// Computes the priority of the leaf `key` and puts it in the split queue (scheduling it under
    /// deferral). Leaves that cannot split (finest level) are not queued.
    pub fn queue_triangle(&mut self, key: TriangleKey) {
        if let Some(priority) = self.triangle_priority(key) {
            self.queues.split.push(key, priority);
        }
    }

    /// The priority of the leaf `key` (scheduled under deferral); `None` when it cannot split.
    fn triangle_priority(&mut self, key: TriangleKey) -> Option<QueueKey> {
        let triangle = self.bintree.get(key);
        if triangle.geometry.tie == 0 {
            return None; // finest level: cannot split
        }
        let tie = triangle.geometry.tie;
        self.counters.evaluations += 1;
        self.counters.elements += 1;
        let value = if self.schedules(0) {
            let wedgie = self.context().measure(triangle);
            self.schedule_triangle(key, &wedgie);
            wedgie.value
        } else {
            self.context().priority(triangle)
        };
        Some(QueueKey::with_tie(value, tie))
    }

    /// Computes the priority of the diamond queued under `primary` and puts it in the merge
    /// queue (scheduling it under deferral).
    pub fn queue_diamond(&mut self, primary: TriangleKey) {
        if let Some(priority) = self.diamond_priority(primary) {
            self.queues.merge.push(primary, priority);
        }
    }

    /// The priority of the diamond queued under `primary` (scheduled under deferral).
    fn diamond_priority(&mut self, primary: TriangleKey) -> Option<QueueKey> {
        let vertex = self.bintree.get(primary).split_vertex()?;
        let parents = diamond_parents(&self.bintree, primary);
        let scheduling = self.schedules(1);
        self.counters.elements += 1;
        let mut wedgies: [Option<Wedgie>; 2] = [None, None];
        let mut value: f64 = 0.0;
        for (slot, parent) in parents.into_iter().enumerate() {
            let Some(parent) = parent else {
                continue;
            };
            self.counters.evaluations += 1;
            let triangle = self.bintree.get(parent);
            if scheduling {
                let wedgie = self.context().measure(triangle);
                value = value.max(wedgie.value);
                wedgies[slot] = Some(wedgie);
            } else {
                value = value.max(self.context().priority(triangle));
            }
        }
        if scheduling {
            self.schedule_diamond(primary, value, &wedgies);
        }
        Some(QueueKey::diamond(self.bintree.lattice(), value, vertex))
    }

    fn schedule_triangle(&mut self, key: TriangleKey, wedgie: &Wedgie) {
        let Some(deferral) = &self.deferral else {
            return;
        };
        let schedule = frames_at_most(
            wedgie,
            deferral.floor,
            self.motion,
            self.view.scale(),
            self.view.near(),
        );
        self.put_on_ring(key, schedule);
    }

    fn schedule_diamond(
        &mut self,
        primary: TriangleKey,
        value: f64,
        wedgies: &[Option<Wedgie>; 2],
    ) {
        let Some(deferral) = &self.deferral else {
            return;
        };
        // At or below H: due next frame. Above: as long as one parent provably stays above.
        let mut schedule = Schedule::After(0);
        if value > deferral.ceiling {
            for wedgie in wedgies.iter().flatten() {
                let parent = frames_above(
                    wedgie,
                    deferral.ceiling,
                    self.motion,
                    self.view.scale(),
                    self.view.near(),
                );
                schedule = match (schedule, parent) {
                    (_, Schedule::Never) | (Schedule::Never, _) => Schedule::Never,
                    (Schedule::After(a), Schedule::After(b)) => Schedule::After(a.max(b)),
                };
            }
        } else if wedgies.iter().flatten().all(|w| w.constant) {
            schedule = Schedule::Never;
        }
        self.put_on_ring(primary, schedule);
    }

    fn put_on_ring(&mut self, key: TriangleKey, schedule: Schedule) {
        let frame = self.frame;
        let Some(deferral) = &mut self.deferral else {
            return;
        };
        let due = match schedule {
            Schedule::Never => u64::MAX,
            Schedule::After(frames) => deferral.schedule(frame, frames, key),
        };
        self.bintree.get_mut(key).due = due;
    }

    // ----- Recomputation ------------------------------------------------------------------

    /// Recomputes every priority of the split queue (`queue` 0) or the merge queue (1). With
    /// `schedule`, each is scheduled now (the band must be set); without, the queue waits for
    /// the end of the frame's schedules (or for the next frame's full recomputation).
    pub fn recompute_queue(&mut self, queue: usize, schedule: bool) {
        if queue == 1 && !self.track_merges {
            return;
        }
        self.scheduling[queue] = if schedule {
            Scheduling::Scheduled
        } else {
            Scheduling::AwaitingSchedule
        };
        let mut keys = std::mem::take(&mut self.scratch);
        let mut priorities = std::mem::take(&mut self.priorities);
        keys.clear();
        priorities.clear();
        if queue == 0 {
            // The bucketed queue lists its keys in slot order, so the triangles' slots are read
            // one after the other.
            self.queues.split.keys_into(&mut keys);
            for &key in &keys {
                if let Some(priority) = self.triangle_priority(key) {
                    priorities.push((key, priority));
                }
            }
            self.queues.split.replace_all(&priorities);
        } else {
            self.queues.merge.keys_into(&mut keys);
            for &key in &keys {
                if let Some(priority) = self.diamond_priority(key) {
                    priorities.push((key, priority));
                }
            }
            self.queues.merge.replace_all(&priorities);
        }
        self.scratch = keys;
        self.priorities = priorities;
    }

    /// Recomputes the priorities that are due this frame (deferral).
    pub fn recompute_due(&mut self) {
        let frame = self.frame;
        let Some(deferral) = &mut self.deferral else {
            return;
        };
        let due = deferral.take_due(frame);
        for &key in &due {
            let Some(triangle) = self.bintree.triangles.get(key) else {
                continue;
            };
            if triangle.due != frame {
                continue;
            }
            if triangle.is_leaf() {
                if self.queues.split.contains(key) {
                    self.queue_triangle(key);
                }
            } else if self.queues.merge.contains(key) {
                self.queue_diamond(key);
            }
        }
        if let Some(deferral) = &mut self.deferral {
            deferral.give_back(frame, due);
        }
    }

    /// Recomputes what a change of culling flags affects: a leaf's priority and strip, a split
    /// triangle's diamond. `skip_priorities` when every priority is recomputed anyway.
    pub fn apply_flag_changes(&mut self, skip_priorities: bool) {
        let changes = std::mem::take(&mut self.flag_changes);
        for &key in &changes {
            let triangle = self.bintree.get(key);
            if triangle.is_leaf() {
                if self.stripped(key) {
                    strips::attach(&mut self.bintree, key);
                } else {
                    strips::detach(&mut self.bintree, key);
                }
                if !skip_priorities && self.queues.split.contains(key) {
                    self.queue_triangle(key);
                }
            } else if !skip_priorities && self.track_merges {
                let primary = primary_parent(&self.bintree, key);
                if self.queues.merge.contains(primary) {
                    self.queue_diamond(primary);
                }
            }
        }
        self.flag_changes = changes;
        self.flag_changes.clear();
    }

    /// §7.1: brings every triangle's culling flags up to date for this frame.
    pub fn update_flags(&mut self) {
        if !self.config.culling_flags {
            return;
        }
        let mut stack = std::mem::take(&mut self.flag_stack);
        let mut changes = std::mem::take(&mut self.flag_changes);
        let frustum = self.view.frustum;
        let counts = cull::update_flags(&mut self.bintree, &frustum, &mut stack, &mut changes);
        self.counters.flag_tests += counts.tests;
        self.flag_stack = stack;
        self.flag_changes = changes;
    }

    /// After the frame's loop: schedules the queues that were recomputed without schedules, and
    /// moves the band (target mode) with the final crossover. Raising G or lowering H is always
    /// safe; a queue awaiting schedules takes the band the crossover asks for.
    pub fn finish_deferral(&mut self) {
        let Some(deferral) = &mut self.deferral else {
            return;
        };
        if self.config.goal_is_target() {
            let crossover = self.queues.top_split().map_or(0.0, |(_, k)| k.value);
            let (floor, ceiling) = if crossover.is_finite() && crossover > 0.0 {
                (
                    crossover / (1.0 + BAND_MARGIN),
                    crossover * (1.0 + BAND_MARGIN),
                )
            } else {
                (0.0, f64::INFINITY)
            };
            if self.scheduling[0] == Scheduling::AwaitingSchedule || floor > deferral.floor {
                deferral.floor = floor;
            }
            if self.scheduling[1] == Scheduling::AwaitingSchedule || ceiling < deferral.ceiling {
                deferral.ceiling = ceiling;
            }
        }
        for queue in [0, 1] {
            if self.scheduling[queue] == Scheduling::AwaitingSchedule {
                self.schedule_queue(queue);
            }
        }
    }

    /// Schedules every element of a queue whose priorities are exact this frame.
    fn schedule_queue(&mut self, queue: usize) {
        if queue == 1 && !self.track_merges {
            self.scheduling[1] = Scheduling::Scheduled;
            return;
        }
        self.scheduling[queue] = Scheduling::Scheduled;
        let mut keys = std::mem::take(&mut self.scratch);
        keys.clear();
        if queue == 0 {
            self.queues.split.keys_into(&mut keys);
            for &key in &keys {
                self.counters.evaluations += 1;
                let wedgie = self.context().measure(self.bintree.get(key));
                self.schedule_triangle(key, &wedgie);
            }
        } else {
            self.queues.merge.keys_into(&mut keys);
            for &key in &keys {
                self.queue_diamond(key);
            }
        }
        self.scratch = keys;
    }
}
