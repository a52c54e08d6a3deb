//! The `selftest` pass: runs `kernels::selftest` over a batch of cases on the device or on
//! the CPU.

use kernels::selftest::{SelfTestCase, SelftestIo, U32_OUTPUTS_PER_CASE};

use super::{Named, Pass};
use crate::gpu::{Gpu, GpuError};

/// A batch of self-test cases with their inputs.
#[derive(Clone, Debug, Default)]
pub struct SelfTestBatch {
    #[allow(missing_docs)] // named for what they are
    pub cases: Vec<SelfTestCase>,
    /// Their inputs, at each case's `input` offset.
    pub inputs: Vec<f32>,
    /// Total float outputs.
    pub float_outputs: usize,
}

/// What a run of the batch produced.
#[derive(Clone, Debug, PartialEq)]
pub struct SelfTestOutputs {
    /// Float outputs, at each case's `output` offset.
    pub floats: Vec<f32>,
    /// Integer outputs, `U32_OUTPUTS_PER_CASE` per case.
    pub words: Vec<u32>,
}

impl SelfTestBatch {
    /// Appends a case, assigning its input and output offsets.
    pub fn push(&mut self, mut case: SelfTestCase, inputs: &[f32]) {
        assert_eq!(inputs.len(), case.inputs(), "inputs of a {:?}", case);
        case.input = self.inputs.len() as u32;
        case.output = self.float_outputs as u32;
        self.inputs.extend_from_slice(inputs);
        self.float_outputs += case.float_outputs();
        self.cases.push(case);
    }

    fn zeroed_outputs(&self) -> SelfTestOutputs {
        SelfTestOutputs {
            floats: vec![0.0; self.float_outputs],
            words: vec![0; self.cases.len() * U32_OUTPUTS_PER_CASE],
        }
    }

    /// Runs the kernel body on the CPU, case after case.
    pub fn run_cpu(&self) -> SelfTestOutputs {
        let mut out = self.zeroed_outputs();
        let io = SelftestIo {
            cases: &self.cases,
            inputs: &self.inputs,
            out_f: &mut out.floats,
            out_u: &mut out.words,
        };
        io.run(self.cases.len());
        out
    }

    /// Runs `selftest_cs` on the device, one invocation per case.
    pub fn run_gpu(&self, gpu: &Gpu) -> Result<SelfTestOutputs, GpuError> {
        use kernels::selftest::{BINDINGS, BINDS_SCENE, ENTRY_POINT};
        let zero = self.zeroed_outputs();
        let cases = gpu.storage_from("selftest cases", &self.cases);
        let inputs = gpu.storage_from("selftest inputs", &self.inputs);
        let floats = gpu.storage_from("selftest floats", &zero.floats);
        let words = gpu.storage_from("selftest words", &zero.words);
        let named = |buffer, element| Some(Named { buffer, element });
        let find = |name: &str| match name {
            "cases" => named(&cases, std::any::type_name::<SelfTestCase>()),
            "inputs" => named(&inputs, std::any::type_name::<f32>()),
            "out_f" => named(&floats, std::any::type_name::<f32>()),
            "out_u" => named(&words, std::any::type_name::<u32>()),
            _ => None,
        };
        let pass = Pass::new(gpu, ENTRY_POINT, BINDINGS, BINDS_SCENE, &find)?;
        let mut encoder = gpu.device.create_command_encoder(&Default::default());
        pass.encode(gpu, &mut encoder, self.cases.len() as u32);
        gpu.queue.submit([encoder.finish()]);
        Ok(SelfTestOutputs {
            floats: gpu.read(&floats, zero.floats.len())?,
            words: gpu.read(&words, zero.words.len())?,
        })
    }
}
