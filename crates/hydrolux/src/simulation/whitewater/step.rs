//! One white-water step on the GPU and the steps a stretch of the clock
//! brings (the order of a step is the CPU twin's, `hydrolux_core::whitewater`).

use super::*;

impl Whitewater {
    /// Follow `clock_steps` more steps of the clock: the steps of ours due
    /// in them, as (clock steps before it, its time). Steps more than
    /// `memory` before `frame_end` (the clock step the frame reaches) are
    /// not simulated: a jump forgets everything once and starts that far
    /// back, however many batches the jump is split into.
    pub fn schedule(
        &mut self,
        clock_steps: u64,
        frame_end: u64,
        queue: &wgpu::Queue,
    ) -> Vec<(u64, f64)> {
        let first = self.clock_steps / self.stride;
        let end = self.clock_steps + clock_steps;
        let last = end / self.stride;
        let horizon = (frame_end / self.stride).saturating_sub(self.memory_steps);
        let mut start = first;
        if horizon > first {
            start = horizon.min(last);
            if !self.forgotten {
                self.reset_buffers(queue);
                self.pending.clear();
                self.forgotten = true;
            }
        }
        let mut out = Vec::new();
        let mut at = self.clock_steps;
        for s in start + 1..=last {
            let boundary = s * self.stride;
            out.push((boundary.saturating_sub(at), boundary as f64 / CLOCK_HZ as f64));
            at = boundary.max(at);
        }
        self.clock_steps = end;
        self.foam.start_at(self.foam.steps().max(start));
        out
    }

    /// Record one step into `encoder` (its uniforms are written now: one
    /// step per submission).
    pub fn record_step(
        &mut self,
        queue: &wgpu::Queue,
        encoder: &mut wgpu::CommandEncoder,
        surface: &wgpu::BindGroup,
        input: StepInput,
    ) {
        if !self.grid.periodic {
            self.grid = FoamGrid::centred(
                self.grid.cells,
                self.grid.cell * self.grid.cells as f32,
                input.centre,
            );
        }
        let mut splashes = std::mem::take(&mut self.pending);
        splashes.extend(input.splashes);
        if splashes.len() > SPLASH_CAPACITY as usize {
            self.pending = splashes.split_off(SPLASH_CAPACITY as usize);
        }
        let mut first = 0;
        for s in &mut splashes {
            s.first = first;
            if self.run & RUN_PARTICLES == 0 {
                s.spray = 0;
                s.bubbles = 0;
            }
            first += s.spray + s.bubbles;
        }
        if !splashes.is_empty() {
            queue.write_buffer(&self.splashes, 0, bytemuck::cast_slice(&splashes));
        }
        let n = self.grid.cells;
        let (cam, reach) = (input.camera, PARTICLE_REACH);
        let domain = if self.grid.periodic {
            [cam[0] - reach, cam[1] - reach, cam[0] + reach, cam[1] + reach]
        } else {
            let lo = [0, 1].map(|a| self.grid.low[a] as f32 * self.grid.cell);
            let side = self.grid.cell * n as f32;
            [lo[0], lo[1], lo[0] + side, lo[1] + side]
        };
        let parity = self.foam.parity();
        let u = WhitewaterUniforms {
            grid_low: self.grid.low,
            grid_cells: n as i32,
            grid_periodic: self.grid.periodic as i32,
            cell: self.grid.cell,
            dt: self.dt,
            foam_keep: self.keep,
            fold_threshold: self.threshold,
            drift: self.drift,
            fold_gain: FOLD_GAIN,
            ripple_gain: RIPPLE_GAIN,
            step: self.foam.steps() as u32,
            splash_count: splashes.len() as u32,
            capacity: self.capacity,
            parity: parity as u32,
            wind: self.wind,
            floor_depth: self.floor_depth,
            max_age: MAX_AGE,
            domain,
            drop_radius: SPRAY_DROP_RADIUS,
            spray_rate: self.spray_rate,
            bubble_rate: self.bubble_rate,
            emission_radius: EMISSION_RADIUS,
            camera: cam,
            run: self.run,
            landing_stride: self.stride as u32,
            deposits_base: COUNTERS,
            gained_base: COUNTERS + n * n,
            heads_base: COUNTERS + n * n + self.capacity,
            bucket_mask: self.table - 1,
            landing_volume: self.landing_volume,
            bubble_mobility: self.bubble_mobility,
            _pad2: 0,
            _pad3: 0,
        };
        queue.write_buffer(&self.params, 0, bytemuck::bytes_of(&u));
        let group = &self.foam.current().group;
        let p = &self.pipelines;
        let particles = self.run & RUN_PARTICLES != 0;
        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some("whitewater begin"),
            timestamp_writes: None,
        });
        pass.set_bind_group(0, group, &[]);
        pass.set_bind_group(1, surface, &[]);
        pass.set_bind_group(2, &self.args_group, &[]);
        pass.set_pipeline(&p.begin);
        pass.dispatch_workgroups(1, 1, 1);
        drop(pass);
        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some("whitewater step"),
            timestamp_writes: None,
        });
        pass.set_bind_group(0, group, &[]);
        pass.set_bind_group(1, surface, &[]);
        if particles {
            pass.set_pipeline(&p.hash_clear);
            pass.dispatch_workgroups(self.table.div_ceil(64), 1, 1);
            pass.set_bind_group(2, &self.kicks_group, &[]);
            for pipeline in [&p.hash_insert, &p.merge_pick, &p.merge_apply, &p.update] {
                pass.set_pipeline(pipeline);
                pass.dispatch_workgroups_indirect(&self.args, 0);
            }
        }
        if let Some((log, log_group)) = &self.log {
            pass.set_bind_group(1, log_group, &[]);
            pass.set_pipeline(&p.plunge);
            pass.dispatch_workgroups_indirect(log, crate::simulation::liquid::LANDING_DISPATCH_AT);
            pass.set_bind_group(1, surface, &[]);
        }
        pass.set_pipeline(&p.foam_step);
        pass.dispatch_workgroups((n * n).div_ceil(64), 1, 1);
        if particles && first > 0 {
            pass.set_pipeline(&p.emit);
            pass.dispatch_workgroups(first.div_ceil(64), 1, 1);
        }
        drop(pass);
        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some("whitewater finish"),
            timestamp_writes: None,
        });
        pass.set_bind_group(0, group, &[]);
        pass.set_bind_group(1, surface, &[]);
        pass.set_bind_group(2, &self.args_group, &[]);
        pass.set_pipeline(&p.finish);
        pass.dispatch_workgroups(1, 1, 1);
        drop(pass);
        self.foam.swap();
        self.forgotten = false;
        self.mips_due = true;
    }

    /// Filter the cover into its mips (once per frame, after the steps).
    pub fn record_mips(&mut self, encoder: &mut wgpu::CommandEncoder, downsampler: &Downsampler) {
        if !self.mips_due {
            return;
        }
        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some("foam cover mips"),
            timestamp_writes: None,
        });
        downsampler.record(&mut pass, &self.cover_chain);
        self.mips_due = false;
    }
}
