//! Candidates as a label set over the exact measure's surface samples: per
//! label a name, a kind, a mirror and the samples it holds. Parts label
//! every sample once (its texel's part, as the PIdT does); display patches
//! overlap, so a sample may carry several labels. Stored per sample (what
//! the per-eye-frame loop walks): its part, and its patches as compressed
//! rows (offsets into one array), so millions of samples cost a few bytes
//! each.

use super::patches::PlacedPatch;
use crate::exact::types::SurfaceSamples;

/// `part` or `patch`, as `placement-frames.csv` spells it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum LabelKind {
    Part,
    Patch,
}

impl LabelKind {
    pub(crate) fn name(self) -> &'static str {
        match self {
            LabelKind::Part => "part",
            LabelKind::Patch => "patch",
        }
    }
}

/// Candidates and which samples each holds.
#[derive(Debug, Clone, Default, PartialEq)]
pub(crate) struct LabelSet {
    pub names: Vec<String>,
    pub kinds: Vec<LabelKind>,
    /// The left/right mirror image's name, where there is one.
    pub mirrors: Vec<Option<String>>,
    /// Per label: the area of its samples, m² (of the sampled texels).
    pub area_m2: Vec<f64>,
    /// Per label: a display patch's exact outline (vehicle frame), `None` for a part.
    pub outlines: Vec<Option<[glam::DVec3; 4]>>,
    /// Per sample: its part's label.
    pub part_of_sample: Vec<u32>,
    /// Per sample `s`: its patch labels are `patch_labels[patch_offsets[s]..patch_offsets[s + 1]]`.
    pub patch_offsets: Vec<u32>,
    pub patch_labels: Vec<u32>,
}

impl LabelSet {
    /// One label per part, each sample in its texel's part.
    pub(crate) fn parts(part_names: &[String], samples: &SurfaceSamples) -> LabelSet {
        let mut set = LabelSet {
            names: part_names.to_vec(),
            kinds: vec![LabelKind::Part; part_names.len()],
            mirrors: part_names.iter().map(|name| mirrored_part(name, part_names)).collect(),
            area_m2: vec![0.0; part_names.len()],
            outlines: vec![None; part_names.len()],
            part_of_sample: vec![0; samples.samples.len()],
            patch_offsets: vec![0; samples.samples.len() + 1],
            patch_labels: Vec::new(),
        };
        for texel in &samples.texels {
            for index in texel.first..texel.first + texel.count {
                set.part_of_sample[index as usize] = texel.part;
                set.area_m2[texel.part as usize] += samples.samples[index as usize].area_m2;
            }
        }
        set
    }

    /// Adds one label per placed patch, holding its member samples.
    pub(crate) fn add_patches(&mut self, patches: &[PlacedPatch], samples: &SurfaceSamples) {
        let first_label = self.names.len() as u32;
        let mut per_sample = vec![0u32; samples.samples.len()];
        for patch in patches {
            self.names.push(patch.name.clone());
            self.kinds.push(LabelKind::Patch);
            self.mirrors.push(patch.mirror.clone());
            self.outlines.push(Some(patch.outline()));
            self.area_m2.push(patch.members.iter().map(|&s| samples.samples[s as usize].area_m2).sum());
            for &sample in &patch.members {
                per_sample[sample as usize] += 1;
            }
        }
        // Compressed rows: existing patch labels first, then the new ones.
        let old_offsets = std::mem::take(&mut self.patch_offsets);
        let old_labels = std::mem::take(&mut self.patch_labels);
        let mut offsets = Vec::with_capacity(per_sample.len() + 1);
        offsets.push(0u32);
        for (s, &new) in per_sample.iter().enumerate() {
            let old = old_offsets[s + 1] - old_offsets[s];
            offsets.push(offsets[s] + old + new);
        }
        let mut labels = vec![0u32; offsets[per_sample.len()] as usize];
        let mut fill: Vec<u32> = offsets[..per_sample.len()].to_vec();
        for (s, slot) in fill.iter_mut().enumerate() {
            for &label in &old_labels[old_offsets[s] as usize..old_offsets[s + 1] as usize] {
                labels[*slot as usize] = label;
                *slot += 1;
            }
        }
        for (index, patch) in patches.iter().enumerate() {
            for &sample in &patch.members {
                labels[fill[sample as usize] as usize] = first_label + index as u32;
                fill[sample as usize] += 1;
            }
        }
        self.patch_offsets = offsets;
        self.patch_labels = labels;
    }

    /// The labels of sample `s`: its part, then its patches.
    pub(crate) fn of_sample(&self, s: usize) -> impl Iterator<Item = u32> + '_ {
        let patches = &self.patch_labels[self.patch_offsets[s] as usize..self.patch_offsets[s + 1] as usize];
        std::iter::once(self.part_of_sample[s]).chain(patches.iter().copied())
    }

    /// How many candidates.
    pub(crate) fn count(&self) -> usize {
        self.names.len()
    }
}

/// The part named as `name` with `left` and `right` swapped, if there is one.
fn mirrored_part(name: &str, part_names: &[String]) -> Option<String> {
    let swapped: Vec<String> = name
        .split('_')
        .map(|word| match word {
            "left" => "right".to_string(),
            "right" => "left".to_string(),
            other => other.to_string(),
        })
        .collect();
    let swapped = swapped.join("_");
    (swapped != name && part_names.contains(&swapped)).then_some(swapped)
}
