//! The LVLM grounding path: a vision-language model annotates the object and its parts from
//! rendered views and chooses each movable part's joint among geometric candidates
//! (`uniphys_annotate`); its values replace the built-in grounder's estimates in the record,
//! so verification and export work unchanged and every value names the model.
//!
//! The articulation tree comes from the model's motion graph: its movable parts and their
//! co-moving groups; parts it leaves unattached are fixed to the root by the grounder's
//! completion of declared joints.

use std::path::PathBuf;
use std::sync::Arc;

use uniphys_annotate::{AnnotateInput, AnnotateOptions, annotate};
use uniphys_geometry::{DMat3, DVec3, MeshAsset, TriMesh, display_rgba};
use uniphys_ground::{PartInput, RigidMass, articulate};
use uniphys_lvlm::{
    AnswerCache, CostLedger, DirCache, LvlmClient, LvlmConfig, NoCache, NoRateLimit, RateLimiter,
};
use uniphys_types::AssetRecord;

use crate::PipelineResult;
use crate::grounding::Prepared;

/// How to reach the LVLM and what the stage may spend.
#[derive(Clone, Default)]
pub struct LvlmOptions {
    /// Server, model, key, reasoning effort, timeouts, retries, concurrency, prices.
    pub client: LvlmConfig,
    /// Most USD this asset may cost; `None` for no limit.
    pub budget_usd: Option<f64>,
    /// Directory of the answer cache (a retried run does not pay twice); `None` for no cache.
    pub cache_dir: Option<PathBuf>,
    /// An answer cache shared with other processes (the service passes one in its object
    /// store); used instead of `cache_dir` when set.
    pub cache: Option<Arc<dyn AnswerCache>>,
    /// Rate limiter shared with other clients (the service passes its fleet-wide Redis
    /// limiter); `None` for no limit beyond the client's concurrency.
    pub rate_limiter: Option<Arc<dyn RateLimiter>>,
    /// Render sizes, sampling, part limit.
    pub annotate: AnnotateOptions,
}

impl std::fmt::Debug for LvlmOptions {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("LvlmOptions")
            .field("client", &self.client)
            .field("budget_usd", &self.budget_usd)
            .field("cache_dir", &self.cache_dir)
            .field("cache", &self.cache.as_ref().map(|_| "<shared>"))
            .field(
                "rate_limiter",
                &self.rate_limiter.as_ref().map(|_| "<shared>"),
            )
            .field("annotate", &self.annotate)
            .finish()
    }
}

/// What the LVLM grounding wrote: notes for the report, which depend only on the asset and the
/// answers (a retried stage writes the same bytes), and this attempt's accounting (requests,
/// cache hits, tokens, cost, times), which does not and goes to the stage's progress summary.
pub(crate) struct LvlmGrounding {
    pub(crate) notes: Vec<String>,
    pub(crate) accounting: String,
}

/// Replaces part properties (and masses), object name, category and mass, and the joints in
/// `record` with the model's answers.
pub(crate) fn ground_lvlm(
    asset: &MeshAsset,
    prepared: &[Prepared],
    colliders: &[Vec<TriMesh>],
    record: &mut AssetRecord,
    options: &LvlmOptions,
) -> PipelineResult<LvlmGrounding> {
    let cache: Arc<dyn AnswerCache> = match (&options.cache, &options.cache_dir) {
        (Some(shared), _) => shared.clone(),
        (None, Some(dir)) => Arc::new(DirCache::new(dir.clone())?),
        (None, None) => Arc::new(NoCache),
    };
    let limiter: Arc<dyn RateLimiter> = options
        .rate_limiter
        .clone()
        .unwrap_or_else(|| Arc::new(NoRateLimit));
    let client = LvlmClient::new(options.client.clone(), limiter, cache)?;
    let ledger = CostLedger::new(options.budget_usd);
    let meshes: Vec<TriMesh> = asset.parts.iter().map(|p| p.mesh.clone()).collect();
    let colours: Vec<[f32; 4]> = asset
        .parts
        .iter()
        .map(|p| display_rgba(&p.mesh, &asset.materials, &asset.textures))
        .collect();
    let names: Vec<String> = asset.parts.iter().map(|p| p.name.clone()).collect();
    let annotation = annotate(
        &AnnotateInput {
            object_name: &record.name,
            part_meshes: &meshes,
            part_colours: &colours,
            part_names: &names,
        },
        &client,
        &ledger,
        &options.annotate,
    )?;

    for (part, properties) in record.parts.iter_mut().zip(&annotation.parts) {
        part.replace_properties(properties.clone());
    }
    record.object.name = annotation.object.name.clone();
    record.object.category = annotation.object.category.clone();
    record.object.mass_kg = annotation.object.mass_kg.clone();

    let masses: Vec<RigidMass> = record
        .parts
        .iter()
        .map(|p| RigidMass {
            mass_kg: p.mass.mass_kg.value,
            com: DVec3::from_array(p.mass.com_in_object_m),
            inertia_about_com_kg_m2: DMat3::from_cols_array_2d(&p.mass.inertia_about_com_kg_m2)
                .transpose(),
        })
        .collect();
    let parts: Vec<PartInput<'_>> = asset
        .parts
        .iter()
        .zip(prepared)
        .zip(&masses)
        .zip(colliders)
        .map(|(((p, prep), mass), hulls)| PartInput {
            name: &p.name,
            mesh: &p.mesh,
            volume_m3: prep.mass.volume_m3,
            mass: *mass,
            colliders: hulls,
        })
        .collect();
    let articulation = articulate(&parts, &annotation.joints)?;
    record.root = articulation.root;
    record.joints = articulation.joints;
    record.validate()?;

    let accounting = format!(
        "LVLM: {} requests ({} from the cache), {} prompt + {} completion tokens, {:.4} USD{}; {} images rendered in {:.3} s, properties request {:.3} s, articulation requests {:.3} s",
        annotation.cost.total.calls,
        annotation.cost.total.cache_hits,
        annotation.cost.total.prompt_tokens,
        annotation.cost.total.completion_tokens,
        annotation.cost.total.cost_usd,
        options
            .budget_usd
            .map(|b| format!(" of a {b:.4} USD budget"))
            .unwrap_or_default(),
        annotation.timings.images,
        annotation.timings.render_secs,
        annotation.timings.properties_request_secs,
        annotation.timings.articulation_secs
    );
    let mut notes = vec![format!(
        "grounded by the LVLM {} (prompt {}) at {}",
        annotation.provider, annotation.prompt_version, options.client.base_url,
    )];
    notes.extend(
        annotation
            .motion_issues
            .iter()
            .map(|i| format!("LVLM motion graph: {}", i.message)),
    );
    notes.extend(annotation.repairs.iter().map(|r| {
        format!(
            "LVLM {} answer repaired after: {}",
            r.subject,
            r.violations.join("; ")
        )
    }));
    notes.extend(annotation.articulation_failures.iter().map(|f| {
        format!(
            "LVLM could not choose the joint of {}: {}; fixed to its parent",
            uniphys_types::PartId(f.label.saturating_sub(1)),
            f.reason
        )
    }));
    notes.extend(articulation.notes);
    Ok(LvlmGrounding { notes, accounting })
}
