//! The viewer page of `holoc view`: one self-contained HTML file (no network) that shows an
//! exported house with three.js (bundled by `scripts/bundle_viewer.sh` into
//! `assets/viewer/three-bundle.js`, MIT licence beside it) and the page's own script
//! (`assets/viewer/app.js`). The page's data is one JSON block: the GLB in base64, a label per
//! room (its id, type and the centre of its floor), and per object the relations of the build
//! report when one is given.

use base64::Engine as _;
use serde_json::{json, Value};

use crate::geometry as geo;
use crate::lower::thor::{House, Object};

/// three.js and the addons the page uses, minified.
const THREE_BUNDLE: &str = include_str!("../../assets/viewer/three-bundle.js");
/// The page's script.
const APP_JS: &str = include_str!("../../assets/viewer/app.js");

const STYLE: &str = "html,body{margin:0;height:100%;overflow:hidden;font:14px system-ui,sans-serif;background:#f2f1ee}\
#app,#app canvas,.labels{position:absolute;inset:0}\
.labels{pointer-events:auto}\
.room-label{padding:2px 6px;border-radius:4px;background:rgba(255,255,255,.8);color:#222;font-weight:600;pointer-events:none}\
#status{position:absolute;left:8px;bottom:8px;color:#555;pointer-events:none}\
#help{position:absolute;left:8px;top:8px;color:#555;pointer-events:none}\
#panel{position:absolute;right:8px;top:8px;max-width:340px;padding:8px 12px;background:rgba(255,255,255,.95);border:1px solid #ccc;border-radius:6px}\
#panel h2{font-size:15px;margin:4px 0}#panel h3{font-size:13px;margin:8px 0 2px}\
#panel dl{display:grid;grid-template-columns:auto 1fr;gap:2px 8px;margin:0}#panel dt{color:#666}#panel dd{margin:0}\
#panel ul{margin:0;padding-left:16px}.kept{color:#185}.broken{color:#b22}.hint{color:#777}\
#compare{position:absolute;left:8px;top:32px;padding:4px 8px;background:rgba(255,255,255,.9);border-radius:4px}\
.moved{color:#c60}.added{color:#185}.removed{color:#b22}\
body.top #help,body.top #status,body.top #panel,body.top #compare{display:none}";

/// The relations of each object in a build report (`holoc build --report`), keyed by the
/// house's `roomId` and `object_name`: each `{constraint, satisfied}`. A house's `roomId` is
/// the room's label (`living room`) where the report names the room by its id (`living_room`)
/// too, so each object is keyed by both.
fn relations(report: &Value) -> std::collections::BTreeMap<(String, String), Vec<Value>> {
    let mut out = std::collections::BTreeMap::new();
    for room in report.get("layout").and_then(Value::as_array).into_iter().flatten() {
        let Some(name) = room.get("room").and_then(Value::as_str) else { continue };
        let label = room.get("label").and_then(Value::as_str).unwrap_or(name);
        for o in room.get("floor_objects").and_then(Value::as_array).into_iter().flatten() {
            let Some(id) = o.get("object").and_then(Value::as_str) else { continue };
            let list: Vec<Value> = o
                .get("constraints")
                .and_then(Value::as_array)
                .into_iter()
                .flatten()
                .map(
                    |c| json!({"constraint": c.get("constraint"), "satisfied": c.get("satisfied")}),
                )
                .collect();
            out.insert((label.to_string(), id.to_string()), list.clone());
            out.insert((name.to_string(), id.to_string()), list);
        }
    }
    out
}

/// The label and scene id of each room of a build report, keyed by the house's room id (the
/// label).
fn room_names(report: &Value) -> std::collections::BTreeMap<String, (String, String)> {
    let mut out = std::collections::BTreeMap::new();
    for room in report.get("layout").and_then(Value::as_array).into_iter().flatten() {
        let Some(id) = room.get("room").and_then(Value::as_str) else { continue };
        let label = room.get("label").and_then(Value::as_str).unwrap_or(id);
        out.insert(label.to_string(), (label.to_string(), id.to_string()));
        out.entry(id.to_string()).or_insert_with(|| (label.to_string(), id.to_string()));
    }
    out
}

fn collect<'h>(o: &'h Object, out: &mut Vec<&'h Object>) {
    out.push(o);
    for c in &o.children {
        collect(c, out);
    }
}

/// The page's data block.
pub fn page_data(house: &House, glb: &[u8], report: Option<&Value>, title: &str) -> Value {
    page_data_with(house, glb, report, title, None)
}

/// The page's data block, with the changes of a before/after view (see [`page_with`]).
pub fn page_data_with(
    house: &House,
    glb: &[u8],
    report: Option<&Value>,
    title: &str,
    compare: Option<&Value>,
) -> Value {
    let names = report.map(room_names).unwrap_or_default();
    let rooms: Vec<Value> = house
        .rooms
        .iter()
        .map(|r| {
            let outline: Vec<geo::Point> = r.floor_polygon.iter().map(|p| [p.x, p.z]).collect();
            let c = geo::area_centroid(&outline);
            let (label, scene_id) =
                names.get(&r.id).cloned().unwrap_or_else(|| (r.id.clone(), r.id.clone()));
            json!({"id": r.id, "label": label, "sceneId": scene_id, "type": r.room_type,
                "centre": [geo::round6(c[0]), geo::round6(c[1])]})
        })
        .collect();
    let by_name = report.map(relations).unwrap_or_default();
    let mut all = Vec::new();
    for o in &house.objects {
        collect(o, &mut all);
    }
    let mut objects = serde_json::Map::new();
    for o in all {
        let rel = by_name.get(&(o.room_id.clone(), o.object_name.clone())).cloned();
        objects.insert(
            o.id.clone(),
            json!({"roomId": o.room_id, "objectName": o.object_name, "relations": rel.unwrap_or_default()}),
        );
    }
    let mut data = json!({
        "title": title,
        "glb": base64::engine::general_purpose::STANDARD.encode(glb),
        "rooms": rooms,
        "objects": objects,
        "hasReport": report.is_some(),
    });
    if let (Some(c), Some(map)) = (compare, data.as_object_mut()) {
        map.insert("compare".into(), c.clone());
    }
    data
}

/// JSON for inside a `<script>` element: `<`, `>` and `&` (only ever in strings) are written
/// as JSON escapes (`\u003c`, `\u003e`, `\u0026`), so that no text of the house can close
/// the element (`</script>`) or open a comment that swallows it (`<!--<script>`, which leaves
/// the page loading for ever); U+2028 and U+2029 are escaped too, for scripts that read the
/// block as JavaScript. The JSON reads back the same. (The scripts are checked by a test never
/// to hold `</script`.)
fn script_safe(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    for c in text.chars() {
        match c {
            '<' => out.push_str("\\u003c"),
            '>' => out.push_str("\\u003e"),
            '&' => out.push_str("\\u0026"),
            '\u{2028}' => out.push_str("\\u2028"),
            '\u{2029}' => out.push_str("\\u2029"),
            c => out.push(c),
        }
    }
    out
}

fn html_escape(text: &str) -> String {
    text.replace('&', "&amp;").replace('<', "&lt;").replace('>', "&gt;").replace('"', "&quot;")
}

/// The whole page.
pub fn page(house: &House, glb: &[u8], report: Option<&Value>, title: &str) -> String {
    page_with(house, glb, report, title, None)
}

/// The whole page; with `compare`, a before/after view: `house` is the house after, and
/// `compare` is `{"before": name, "moved": [{"id", "from", "to"}], "added": [id],
/// "removed": [{"id", "at", "size", "rotation"}]}` (positions and sizes in metres, AI2-THOR's
/// frame): moved objects get an arrow from where they stood, added ones are green, removed
/// ones a red box where they stood.
pub fn page_with(
    house: &House,
    glb: &[u8],
    report: Option<&Value>,
    title: &str,
    compare: Option<&Value>,
) -> String {
    let data = page_data_with(house, glb, report, title, compare);
    let mut out = String::with_capacity(THREE_BUNDLE.len() + glb.len() * 4 / 3 + 8192);
    out.push_str("<!doctype html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n");
    out.push_str("<meta name=\"viewport\" content=\"width=device-width,initial-scale=1\">\n");
    out.push_str("<title>");
    out.push_str(&html_escape(title));
    out.push_str(" — holoc view</title>\n<style>");
    out.push_str(STYLE);
    out.push_str("</style>\n</head>\n<body>\n");
    out.push_str("<div id=\"app\"></div>\n");
    out.push_str("<div id=\"help\">drag to turn · right-drag to move · wheel to zoom · click an object</div>\n");
    out.push_str("<div id=\"panel\" hidden></div>\n<div id=\"compare\" hidden></div>\n<div id=\"status\">loading…</div>\n");
    out.push_str("<script id=\"holoc-data\" type=\"application/json\">");
    out.push_str(&script_safe(&data.to_string()));
    out.push_str("</script>\n<script>\n");
    out.push_str(THREE_BUNDLE);
    out.push_str("\n</script>\n<script>\n");
    out.push_str(APP_JS);
    out.push_str("\n</script>\n</body>\n</html>\n");
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn scripts_cannot_close_their_element() {
        assert!(!script_safe("a</script>b").contains("</script"));
        let hostile = json!({"id": "<!--<script>a</script>&\u{2028}\u{2029}</SCRIPT >"});
        let safe = script_safe(&hostile.to_string());
        for bad in ['<', '>', '&', '\u{2028}', '\u{2029}'] {
            assert!(!safe.contains(bad), "{safe}");
        }
        assert_eq!(serde_json::from_str::<Value>(&safe).expect("still JSON"), hostile);
        assert!(!THREE_BUNDLE.contains("</script"));
        assert!(!APP_JS.contains("</script"));
    }
}
