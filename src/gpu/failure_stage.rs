//! [`FailureStage`]: the ply failure indices of every resident step on the device
//! (`failure_survey` over the evaluation points, then `failure_reduce` into the step's
//! history row), for models whose materials have strengths.

use super::buffer::Storage;
use super::context::GpuContext;
use super::kernel::Launch;
use super::kernels::{FailureReduce, FailureSurveyKernel};
use super::types::{self, to_device};
use crate::error::{ImpactError, Result};
use crate::kernels::{SurveySetup, FAILURE_FIELDS};

/// Points the survey can number exactly in an f32 record.
const MAX_POINTS: usize = 1 << 24;

pub(super) struct FailureStage {
    survey: FailureSurveyKernel,
    reduce: FailureReduce,
    survey_launch: Launch,
    /// One per row of a submission: launch j writes the record into row j.
    reduce_launches: Vec<Launch>,
    /// Kept alive for the bind groups: the points, operators, strengths and the
    /// workgroups' records.
    buffers: Vec<Storage>,
}

/// Where the stage reads and writes: the displacement, and the rows buffer with its row
/// length, the record's first column and the rows a submission holds.
pub(super) struct StageTarget<'a> {
    pub displacement: &'a wgpu::Buffer,
    pub rows: &'a wgpu::Buffer,
    pub row_len: usize,
    pub column: usize,
    pub chunk_capacity: usize,
}

impl FailureStage {
    pub(super) fn new(ctx: &GpuContext, setup: &SurveySetup, t: &StageTarget) -> Result<Self> {
        let n = setup.points.len();
        if n >= MAX_POINTS {
            return Err(ImpactError::Gpu(format!(
                "{n} ply failure points: the device survey numbers at most {MAX_POINTS}"
            )));
        }
        let points: Vec<types::GpuSurveyPoint> = to_device(&setup.points);
        let strengths: Vec<types::PlyStrength> = to_device(&setup.strengths);
        let operators: Vec<f32> = setup.operators.iter().map(|&x| x as f32).collect();
        let points = Storage::with_data(ctx, "survey.points", &points)?;
        let operators = Storage::with_data(ctx, "survey.operators", &operators)?;
        let strengths = Storage::with_data(ctx, "survey.strengths", &strengths)?;
        let survey = FailureSurveyKernel::new(ctx);
        let reduce = FailureReduce::new(ctx);
        let g = survey.0.grid(n as u32);
        let groups = (g[0] * g[1]) as usize;
        let partials = Storage::new(ctx, "survey.partials", (groups * FAILURE_FIELDS * 4) as u64)?;
        let survey_launch = survey.launch(
            ctx,
            n as u32,
            0,
            0,
            t.displacement,
            &points.buffer,
            &operators.buffer,
            &strengths.buffer,
            &partials.buffer,
        );
        let reduce_launches = (0..t.chunk_capacity)
            .map(|j| {
                let at = (j * t.row_len + t.column) as u32;
                reduce.launch(ctx, groups as u32, 0, at, &partials.buffer, t.rows)
            })
            .collect();
        Ok(FailureStage {
            survey,
            reduce,
            survey_launch,
            reduce_launches,
            buffers: vec![points, operators, strengths, partials],
        })
    }

    /// Dispatches the survey of the current displacement and its record into row `j`.
    pub(super) fn dispatch(&self, pass: &mut wgpu::ComputePass, j: usize) {
        self.survey.0.dispatch(pass, &self.survey_launch);
        let l = &self.reduce_launches[j];
        self.reduce.0.dispatch_with(pass, &l.bind, [1, 1]);
    }

    /// The workgroups of the survey.
    pub(super) fn groups(&self) -> usize {
        self.survey_launch.groups as usize
    }

    /// The workgroups' records.
    pub(super) fn partials(&self) -> &wgpu::Buffer {
        &self.buffers[3].buffer
    }

    /// Bytes held on the device.
    pub(super) fn device_bytes(&self) -> u64 {
        self.buffers.iter().map(|s| s.capacity).sum()
    }
}
