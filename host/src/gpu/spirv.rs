//! What the kernels module declares, read from its SPIR-V words: each entry point's name,
//! workgroup size and bindings — checked against what the host declares for each pass.

/// What a SPIR-V module declares of one compute entry point: its name, workgroup size, and
/// the storage buffers it binds (binding number, and whether it may write them: not
/// decorated `NonWritable`), in binding order.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct EntryInterface {
    /// As `OpEntryPoint` names it (e.g. `trace_cs`).
    pub name: String,
    /// `LocalSize` (x, y, z).
    pub workgroup_size: [u32; 3],
    /// (descriptor set, binding, writable) of each descriptor the entry point's interface
    /// holds, in set and binding order.
    pub bindings: Vec<(u32, u32, bool)>,
}

/// The entry points of a SPIR-V module (SPIR-V ≥ 1.4, where an entry point's interface lists
/// every global variable it uses), in module order.
pub fn spirv_interfaces(words: &[u32]) -> Vec<EntryInterface> {
    const OP_ENTRY_POINT: u32 = 15;
    const OP_EXECUTION_MODE: u32 = 16;
    const OP_DECORATE: u32 = 71;
    const LOCAL_SIZE: u32 = 17;
    const NON_WRITABLE: u32 = 24;
    const BINDING: u32 = 33;
    const DESCRIPTOR_SET: u32 = 34;
    let mut entries: Vec<(u32, String, Vec<u32>)> = Vec::new();
    let mut sizes: Vec<(u32, [u32; 3])> = Vec::new();
    let mut binding_of: std::collections::HashMap<u32, u32> = Default::default();
    let mut set_of: std::collections::HashMap<u32, u32> = Default::default();
    let mut read_only: std::collections::HashSet<u32> = Default::default();
    let mut i = 5; // after the header
    while i < words.len() {
        let count = (words[i] >> 16) as usize;
        if count == 0 || i + count > words.len() {
            break;
        }
        let op = &words[i..i + count];
        match op[0] & 0xffff {
            OP_ENTRY_POINT if count > 3 => {
                // Execution model, function id, the nul-terminated name, then the interface.
                let bytes: Vec<u8> = op[3..].iter().flat_map(|w| w.to_le_bytes()).collect();
                let end = bytes.iter().position(|&b| b == 0).unwrap_or(bytes.len());
                let name_words = end / 4 + 1;
                let name = String::from_utf8_lossy(&bytes[..end]).into_owned();
                entries.push((op[2], name, op[(3 + name_words).min(count)..].to_vec()));
            }
            OP_EXECUTION_MODE if count >= 6 && op[2] == LOCAL_SIZE => {
                sizes.push((op[1], [op[3], op[4], op[5]]))
            }
            OP_DECORATE if count >= 3 && op[2] == NON_WRITABLE => {
                read_only.insert(op[1]);
            }
            OP_DECORATE if count >= 4 && op[2] == BINDING => {
                binding_of.insert(op[1], op[3]);
            }
            OP_DECORATE if count >= 4 && op[2] == DESCRIPTOR_SET => {
                set_of.insert(op[1], op[3]);
            }
            _ => {}
        }
        i += count;
    }
    entries
        .into_iter()
        .map(|(function, name, interface)| {
            let mut bindings: Vec<(u32, u32, bool)> = interface
                .iter()
                .filter_map(|id| {
                    let set = set_of.get(id).copied().unwrap_or(0);
                    binding_of.get(id).map(|b| (set, *b, !read_only.contains(id)))
                })
                .collect();
            bindings.sort_unstable();
            let workgroup_size = sizes.iter().find(|(f, _)| *f == function).map_or([0; 3], |(_, s)| *s);
            EntryInterface { name, workgroup_size, bindings }
        })
        .collect()
}

/// The names of a SPIR-V module's entry points, in module order.
pub fn spirv_entry_points(words: &[u32]) -> Vec<String> {
    spirv_interfaces(words).into_iter().map(|e| e.name).collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::gpu::KERNELS_SPV;
    /// The module built by rust-gpu holds exactly the entry points `kernels` declares, under
    /// their plain names (rust-gpu would otherwise qualify them with the module path).
    #[test]
    fn module_entry_points_are_the_declared_ones() {
        let mut found = spirv_entry_points(&wgpu::util::make_spirv_raw(KERNELS_SPV));
        found.sort();
        let mut declared: Vec<String> = kernels::ENTRY_POINTS.iter().map(|s| s.to_string()).collect();
        declared.sort();
        assert_eq!(found, declared);
    }

    /// Every entry point runs `kernels::WORKGROUP_SIZE` invocations a workgroup (what the host
    /// declares when it hands the module to the driver unchanged, and divides dispatches by),
    /// and binds exactly what its declaration (`kernels::stage`) lists: the same sets, numbers
    /// and writability, so the host's binding lists, made from the declarations, match the
    /// compiled module.
    #[test]
    fn module_workgroups_and_bindings_are_the_declared_ones() {
        let interfaces = spirv_interfaces(&wgpu::util::make_spirv_raw(KERNELS_SPV));
        assert_eq!(interfaces.len(), kernels::KERNELS.len());
        for e in &interfaces {
            assert_eq!(e.workgroup_size, [kernels::WORKGROUP_SIZE, 1, 1], "{}", e.name);
            let kernel = kernels::KERNELS.iter().find(|k| k.entry_point == e.name).expect("declared");
            assert_eq!(e.bindings, kernel.interface(), "{}", e.name);
        }
    }
}
