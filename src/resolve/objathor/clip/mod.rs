//! CLIP's text tower run in process (feature `clip`): the query of `--objathor-scoring clip` is
//! embedded as the original embeds it (open_clip `ViT-L-14`, `laion2b_s32b_b82k`; the same
//! weights in Hugging Face's layout are `laion/CLIP-ViT-L-14-laion2B-s32B-b82K`), with
//! [`candle`](candle_core) on the CPU.
//!
//! A weights folder ([`TextTower::load`]) holds `model.safetensors` (Hugging Face's `CLIPModel`
//! names: `text_model.*` and `text_projection.weight`; only those tensors are read, the vision
//! tower's are skipped), the tokenizer (`vocab.json` + `merges.txt`, or `tokenizer.json`) and
//! `config.json` (its `text_config`: heads, activation, layer-norm epsilon). The sizes are read
//! from the tensors themselves. The model: token and position embeddings, pre-norm transformer
//! blocks with a causal mask, the final layer norm, the output at `<|endoftext|>`, the
//! projection — then L2-normalised.

pub mod bpe;

use std::collections::HashMap;
use std::io::{Read as _, Seek as _};
use std::path::{Path, PathBuf};
use std::sync::{Arc, Mutex};

use candle_core::{DType, Device, Tensor};
use candle_nn::{Embedding, LayerNorm, Linear, Module as _};

pub use bpe::Bpe;

/// The weights file of a folder.
pub const WEIGHTS_FILE: &str = "model.safetensors";

/// The largest safetensors header holoc reads, bytes.
const MAX_HEADER_BYTES: u64 = 64 * 1024 * 1024;

/// The largest tokenizer or config file holoc reads, bytes.
const MAX_TEXT_BYTES: u64 = 64 * 1024 * 1024;

/// What went wrong loading a tower: which of its files, and why.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum LoadError {
    /// The weights (`model.safetensors`) or `config.json`: missing, unreadable or not a CLIP
    /// text tower.
    Weights(PathBuf, String),
    /// The tokenizer files: missing, unreadable or not a CLIP vocabulary.
    Tokenizer(PathBuf, String),
}

/// The activation of the blocks' MLP.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Activation {
    /// `gelu` (exact, with erf): open_clip's `nn.GELU`, the LAION models'.
    Gelu,
    /// `quick_gelu` (`x·σ(1.702x)`): OpenAI's CLIP.
    QuickGelu,
}

/// The sizes and settings of a tower (read from its tensors and `config.json`).
#[derive(Clone, Debug, PartialEq)]
pub struct TowerConfig {
    /// Tokens in the vocabulary.
    pub vocab: usize,
    /// Width of the transformer.
    pub hidden: usize,
    /// Width of the MLP.
    pub intermediate: usize,
    /// Attention heads.
    pub heads: usize,
    /// Transformer blocks.
    pub layers: usize,
    /// Positions (77).
    pub positions: usize,
    /// Length of the output embedding.
    pub projection: usize,
    /// The MLP's activation.
    pub activation: Activation,
    /// The layer norms' epsilon.
    pub eps: f64,
}

struct Block {
    ln1: LayerNorm,
    q: Linear,
    k: Linear,
    v: Linear,
    out: Linear,
    ln2: LayerNorm,
    fc1: Linear,
    fc2: Linear,
}

/// The tensors read from a weights file, taken one by one with their shapes checked.
struct Weights<'a> {
    t: HashMap<String, Tensor>,
    file: &'a Path,
}

impl Weights<'_> {
    fn take(&mut self, name: &str, shape: &[usize]) -> Result<Tensor, LoadError> {
        let bad = |why: String| LoadError::Weights(self.file.to_path_buf(), why);
        let tensor = self
            .t
            .remove(name)
            .ok_or_else(|| bad(format!("it has no tensor `{name}` (not a CLIP model?)")))?;
        if tensor.dims() != shape {
            return Err(bad(format!("`{name}` has the shape {:?}, not {shape:?}", tensor.dims())));
        }
        Ok(tensor)
    }

    fn layer_norm(&mut self, p: &str, width: usize, eps: f64) -> Result<LayerNorm, LoadError> {
        let weight = self.take(&format!("{p}.weight"), &[width])?;
        let bias = self.take(&format!("{p}.bias"), &[width])?;
        Ok(LayerNorm::new(weight, bias, eps))
    }

    fn linear(&mut self, p: &str, out: usize, inp: usize) -> Result<Linear, LoadError> {
        let weight = self.take(&format!("{p}.weight"), &[out, inp])?;
        let bias = self.take(&format!("{p}.bias"), &[out])?;
        Ok(Linear::new(weight, Some(bias)))
    }
}

/// A loaded text tower and its tokenizer.
pub struct TextTower {
    /// The folder it was loaded from.
    pub dir: PathBuf,
    /// Its sizes.
    pub config: TowerConfig,
    tokenizer: Bpe,
    token_embedding: Embedding,
    position_embedding: Tensor,
    blocks: Vec<Block>,
    final_ln: LayerNorm,
    projection: Linear,
    cache: Mutex<HashMap<String, Arc<[f32]>>>,
}

impl std::fmt::Debug for TextTower {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("TextTower")
            .field("dir", &self.dir)
            .field("config", &self.config)
            .finish_non_exhaustive()
    }
}

fn read_text(path: &Path) -> Result<String, String> {
    let meta = std::fs::metadata(path).map_err(|e| e.to_string())?;
    if meta.len() > MAX_TEXT_BYTES {
        return Err(format!("it is larger than {MAX_TEXT_BYTES} bytes"));
    }
    std::fs::read_to_string(path).map_err(|e| e.to_string())
}

/// The tokenizer of a weights folder: `vocab.json` + `merges.txt`, else `tokenizer.json`.
pub fn load_tokenizer(dir: &Path) -> Result<Bpe, LoadError> {
    let vocab = dir.join("vocab.json");
    let merges = dir.join("merges.txt");
    let json = dir.join("tokenizer.json");
    if vocab.is_file() && merges.is_file() {
        let v = read_text(&vocab).map_err(|e| LoadError::Tokenizer(vocab.clone(), e))?;
        let m = read_text(&merges).map_err(|e| LoadError::Tokenizer(merges.clone(), e))?;
        Bpe::from_vocab_merges(&v, &m).map_err(|e| LoadError::Tokenizer(vocab, e))
    } else if json.is_file() {
        let t = read_text(&json).map_err(|e| LoadError::Tokenizer(json.clone(), e))?;
        Bpe::from_tokenizer_json(&t).map_err(|e| LoadError::Tokenizer(json, e))
    } else {
        Err(LoadError::Tokenizer(
            dir.to_path_buf(),
            "there is neither `vocab.json` with `merges.txt` nor `tokenizer.json`".into(),
        ))
    }
}

/// One tensor's entry in a safetensors header.
#[derive(serde::Deserialize)]
struct HeaderEntry {
    dtype: String,
    shape: Vec<usize>,
    data_offsets: (u64, u64),
}

/// Reads the tensors of `file` whose names `wanted` accepts, as float32 on the CPU: only their
/// bytes are read (a full CLIP file is 1.7 GB; its text tower a quarter of it).
pub fn read_safetensors(
    file: &Path,
    wanted: impl Fn(&str) -> bool,
) -> Result<HashMap<String, Tensor>, String> {
    let mut f = std::fs::File::open(file).map_err(|e| e.to_string())?;
    let len = f.metadata().map_err(|e| e.to_string())?.len();
    let mut n = [0u8; 8];
    f.read_exact(&mut n).map_err(|_| "it is too short for a safetensors file".to_string())?;
    let header_len = u64::from_le_bytes(n);
    if header_len > MAX_HEADER_BYTES || header_len + 8 > len {
        return Err(format!("its header length {header_len} does not fit the file"));
    }
    let mut header = vec![0u8; header_len as usize];
    f.read_exact(&mut header).map_err(|e| e.to_string())?;
    let header: HashMap<String, serde_json::Value> = serde_json::from_slice(&header)
        .map_err(|e| format!("its header is not a safetensors JSON header: {e}"))?;
    let data_start = 8 + header_len;
    let mut names: Vec<&String> =
        header.keys().filter(|k| k.as_str() != "__metadata__" && wanted(k)).collect();
    names.sort();
    let mut out = HashMap::new();
    for name in names {
        let entry: HeaderEntry = serde_json::from_value(header[name].clone())
            .map_err(|e| format!("the header entry of `{name}` is not usable: {e}"))?;
        let (begin, end) = entry.data_offsets;
        let elems: usize = entry
            .shape
            .iter()
            .try_fold(1usize, |a, &d| a.checked_mul(d))
            .ok_or_else(|| format!("the shape of `{name}` is too large"))?;
        let width = match entry.dtype.as_str() {
            "F32" => 4,
            "F16" | "BF16" => 2,
            other => {
                return Err(format!("`{name}` is of dtype {other} (F32, F16 or BF16 are read)"))
            }
        };
        if end < begin
            || end - begin != (elems as u64).saturating_mul(width)
            || data_start.saturating_add(end) > len
        {
            return Err(format!("the data offsets of `{name}` do not fit its shape or the file"));
        }
        let mut bytes = vec![0u8; (end - begin) as usize];
        f.seek(std::io::SeekFrom::Start(data_start + begin)).map_err(|e| e.to_string())?;
        f.read_exact(&mut bytes).map_err(|e| e.to_string())?;
        let values: Vec<f32> = match entry.dtype.as_str() {
            "F32" => bytes
                .chunks_exact(4)
                .map(|c| f32::from_le_bytes([c[0], c[1], c[2], c[3]]))
                .collect(),
            "F16" => bytes
                .chunks_exact(2)
                .map(|c| half::f16::from_bits(u16::from_le_bytes([c[0], c[1]])).to_f32())
                .collect(),
            _ => bytes
                .chunks_exact(2)
                .map(|c| f32::from_bits(u32::from(u16::from_le_bytes([c[0], c[1]])) << 16))
                .collect(),
        };
        if values.iter().any(|x| !x.is_finite()) {
            return Err(format!("`{name}` holds values that are not finite"));
        }
        let t = Tensor::from_vec(values, entry.shape, &Device::Cpu).map_err(|e| e.to_string())?;
        out.insert(name.clone(), t);
    }
    Ok(out)
}

/// Writes `tensors` (float32) as a safetensors file: the fixture's and the benchmark's tiny
/// towers.
#[allow(clippy::implicit_hasher, reason = "candle's `save` takes the default hasher's map")]
pub fn write_safetensors(tensors: &HashMap<String, Tensor>, path: &Path) -> Result<(), String> {
    candle_core::safetensors::save(tensors, path).map_err(|e| e.to_string())
}

/// The `text_config` of `config.json` (absent: the LAION ViT-L-14's settings).
fn read_config(dir: &Path, hidden: usize) -> Result<(usize, Activation, f64), String> {
    let path = dir.join("config.json");
    let default_heads = (hidden / 64).max(1);
    if !path.is_file() {
        return Ok((default_heads, Activation::Gelu, 1e-5));
    }
    let value: serde_json::Value = serde_json::from_str(&read_text(&path)?)
        .map_err(|e| format!("`config.json` is not JSON: {e}"))?;
    let text = value.get("text_config").unwrap_or(&value);
    let heads = text
        .get("num_attention_heads")
        .and_then(serde_json::Value::as_u64)
        .map_or(default_heads, |h| h as usize);
    let activation = match text.get("hidden_act").and_then(serde_json::Value::as_str) {
        None | Some("gelu") => Activation::Gelu,
        Some("quick_gelu") => Activation::QuickGelu,
        Some(other) => {
            return Err(format!("`text_config.hidden_act` is `{other}` (gelu or quick_gelu)"))
        }
    };
    let eps = text.get("layer_norm_eps").and_then(serde_json::Value::as_f64).unwrap_or(1e-5);
    if heads == 0 || hidden % heads != 0 {
        return Err(format!("{heads} heads do not divide the width {hidden}"));
    }
    Ok((heads, activation, eps))
}

impl TextTower {
    /// Loads the tower of the weights folder `dir` (see the module's documentation).
    pub fn load(dir: &Path) -> Result<TextTower, LoadError> {
        let tokenizer = load_tokenizer(dir)?;
        let file = dir.join(WEIGHTS_FILE);
        let bad = |why: String| LoadError::Weights(file.clone(), why);
        if !file.is_file() {
            return Err(bad("there is no such file".into()));
        }
        let t = read_safetensors(&file, |n| {
            n.starts_with("text_model.") || n == "text_projection.weight"
        })
        .map_err(bad)?;
        let dims_of = |t: &HashMap<String, Tensor>, name: &str| -> Result<Vec<usize>, LoadError> {
            t.get(name)
                .map(|x| x.dims().to_vec())
                .ok_or_else(|| bad(format!("it has no tensor `{name}` (not a CLIP model?)")))
        };
        let emb = dims_of(&t, "text_model.embeddings.token_embedding.weight")?;
        let pos = dims_of(&t, "text_model.embeddings.position_embedding.weight")?;
        let proj = dims_of(&t, "text_projection.weight")?;
        let fc1 = dims_of(&t, "text_model.encoder.layers.0.mlp.fc1.weight")?;
        let (&[vocab, hidden], &[positions, _], &[projection, _], &[intermediate, _]) =
            (emb.as_slice(), pos.as_slice(), proj.as_slice(), fc1.as_slice())
        else {
            return Err(bad("its embeddings or projection are not matrices".into()));
        };
        let layers = (0..t.len())
            .take_while(|i| {
                t.contains_key(&format!("text_model.encoder.layers.{i}.layer_norm1.weight"))
            })
            .count();
        let (heads, activation, eps) = read_config(dir, hidden).map_err(bad)?;
        if vocab < tokenizer.vocab_len() {
            return Err(bad(format!(
                "its {vocab} token embeddings are fewer than the tokenizer's {} tokens",
                tokenizer.vocab_len()
            )));
        }
        if positions < bpe::CONTEXT_LENGTH {
            return Err(bad(format!(
                "it has {positions} positions, CLIP reads {}",
                bpe::CONTEXT_LENGTH
            )));
        }
        let config = TowerConfig {
            vocab,
            hidden,
            intermediate,
            heads,
            layers,
            positions,
            projection,
            activation,
            eps,
        };
        let mut w = Weights { t, file: &file };
        let final_ln = w.layer_norm("text_model.final_layer_norm", hidden, eps)?;
        let mut blocks = Vec::with_capacity(layers);
        for i in 0..layers {
            let p = format!("text_model.encoder.layers.{i}");
            blocks.push(Block {
                ln1: w.layer_norm(&format!("{p}.layer_norm1"), hidden, eps)?,
                q: w.linear(&format!("{p}.self_attn.q_proj"), hidden, hidden)?,
                k: w.linear(&format!("{p}.self_attn.k_proj"), hidden, hidden)?,
                v: w.linear(&format!("{p}.self_attn.v_proj"), hidden, hidden)?,
                out: w.linear(&format!("{p}.self_attn.out_proj"), hidden, hidden)?,
                ln2: w.layer_norm(&format!("{p}.layer_norm2"), hidden, eps)?,
                fc1: w.linear(&format!("{p}.mlp.fc1"), intermediate, hidden)?,
                fc2: w.linear(&format!("{p}.mlp.fc2"), hidden, intermediate)?,
            });
        }
        let token_embedding = Embedding::new(
            w.take("text_model.embeddings.token_embedding.weight", &[vocab, hidden])?,
            hidden,
        );
        let position_embedding =
            w.take("text_model.embeddings.position_embedding.weight", &[positions, hidden])?;
        let projection =
            Linear::new(w.take("text_projection.weight", &[projection, hidden])?, None);
        Ok(TextTower {
            dir: dir.to_path_buf(),
            config,
            tokenizer,
            token_embedding,
            position_embedding,
            blocks,
            final_ln,
            projection,
            cache: Mutex::new(HashMap::new()),
        })
    }

    /// The tokenizer.
    pub fn tokenizer(&self) -> &Bpe {
        &self.tokenizer
    }

    /// The unit embedding of `text` (remembered: a query asked again costs a look-up).
    pub fn embed(&self, text: &str) -> Result<Arc<[f32]>, String> {
        if let Some(v) = self.cache.lock().ok().and_then(|c| c.get(text).cloned()) {
            return Ok(v);
        }
        let ids = self.tokenizer.tokenize(text);
        let mut v = self.forward(&ids).map_err(|e| e.to_string())?;
        super::features::normalize(&mut v);
        let v: Arc<[f32]> = v.into();
        if let Ok(mut c) = self.cache.lock() {
            c.insert(text.to_string(), v.clone());
        }
        Ok(v)
    }

    /// The projected output at the first `<|endoftext|>` of `ids` (open_clip takes the
    /// argmax of the ids, which is the same token in CLIP's vocabulary), before normalising.
    pub fn forward(&self, ids: &[u32]) -> candle_core::Result<Vec<f32>> {
        if ids.is_empty() {
            return Err(candle_core::Error::Msg("no tokens to embed".into()));
        }
        let n = ids.len().min(self.config.positions);
        let eot = ids[..n]
            .iter()
            .position(|&t| t == self.tokenizer.end_id())
            .unwrap_or(n.saturating_sub(1));
        // Tokens past the end token never reach it under the causal mask.
        let n = eot + 1;
        let input = Tensor::new(&ids[..n], &Device::Cpu)?;
        let mut x = self.token_embedding.forward(&input)?;
        x = x.broadcast_add(&self.position_embedding.narrow(0, 0, n)?)?;
        let heads = self.config.heads;
        let hd = self.config.hidden / heads;
        let scale = 1.0 / (hd as f64).sqrt();
        let mask: Vec<f32> = (0..n)
            .flat_map(|i| (0..n).map(move |j| if j > i { f32::NEG_INFINITY } else { 0.0 }))
            .collect();
        let mask = Tensor::from_vec(mask, (n, n), &Device::Cpu)?;
        for b in &self.blocks {
            let h = b.ln1.forward(&x)?;
            let split = |t: Tensor| -> candle_core::Result<Tensor> {
                t.reshape((n, heads, hd))?.transpose(0, 1)?.contiguous()
            };
            let q = split((b.q.forward(&h)? * scale)?)?;
            let k = split(b.k.forward(&h)?)?;
            let v = split(b.v.forward(&h)?)?;
            let att = q.matmul(&k.t()?.contiguous()?)?.broadcast_add(&mask)?;
            let att = candle_nn::ops::softmax_last_dim(&att)?;
            let o = att.matmul(&v)?.transpose(0, 1)?.contiguous()?.reshape((n, heads * hd))?;
            x = (x + b.out.forward(&o)?)?;
            let h = b.ln2.forward(&x)?;
            let h = b.fc1.forward(&h)?;
            let h = match self.config.activation {
                Activation::Gelu => h.gelu_erf()?,
                Activation::QuickGelu => (&h * candle_nn::ops::sigmoid(&(&h * 1.702)?)?)?,
            };
            x = (x + b.fc2.forward(&h)?)?;
        }
        let x = self.final_ln.forward(&x)?;
        let pooled = x.narrow(0, eot, 1)?;
        let out = self.projection.forward(&pooled)?;
        out.squeeze(0)?.to_dtype(DType::F32)?.to_vec1::<f32>()
    }
}
