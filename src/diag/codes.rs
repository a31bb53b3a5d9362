//! The catalogue of diagnostic codes.
//!
//! The first two digits of a code name the stage that emits it (`E00` driver and files, `E01`
//! parse, `E02` check, `E03` plan, `E04` resolve, `E05` solve, `E06` lower and output, `E07`
//! import, `E08` generate); `W` codes are warnings in the same bands. A number, once used, is never
//! given to anything else. Every code has a page `book/src/diagnostics/<CODE>.md`, embedded here
//! at build time for `holoc explain`.

use super::Severity;

macro_rules! codes {
    ($($code:ident $name:literal $summary:literal;)*) => {
        /// A diagnostic code: stage band, kebab-case name, default severity and book page.
        #[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
        pub enum Code {
            $(
                #[doc = $summary]
                $code,
            )*
        }

        impl Code {
            /// Every code, in catalogue order.
            pub const ALL: &'static [Code] = &[$(Code::$code),*];

            /// The code as written, e.g. `E0201`.
            pub fn as_str(self) -> &'static str {
                match self { $(Code::$code => stringify!($code),)* }
            }

            /// The kebab-case name of the problem, e.g. `unknown-object`.
            pub fn name(self) -> &'static str {
                match self { $(Code::$code => $name,)* }
            }

            /// A one-line summary.
            pub fn summary(self) -> &'static str {
                match self { $(Code::$code => $summary,)* }
            }

            /// The page of the diagnostics catalogue, as Markdown.
            pub fn page(self) -> &'static str {
                match self {
                    $(Code::$code => include_str!(concat!(
                        env!("CARGO_MANIFEST_DIR"), "/book/src/diagnostics/", stringify!($code), ".md"
                    )),)*
                }
            }
        }
    };
}

codes! {
    E0001 "io-error" "a file could not be read or written";
    E0002 "internal-error" "holoc hit a bug; the input may be fine";
    E0003 "invalid-encoding" "a file is not valid UTF-8 text";
    E0004 "invalid-argument" "a command-line value is not usable";
    E0005 "not-a-job" "a line of a batch manifest is not a job";
    E0006 "job-timed-out" "a batch job ran past its time limit and was stopped";
    E0007 "disk-full" "an output could not be written because the disk is full";
    E0008 "missing-shards" "`holoc batch merge` was given the summaries of only some shards";
    E0009 "outside-folder" "a path leads outside the folder it must stay in";
    E0010 "too-many-tokens" "a file holds more words, numbers and signs than holoc reads";

    E0101 "syntax-error" "the text does not follow the grammar of a statement";
    E0102 "unknown-statement" "a line does not start like any statement of its block";
    E0103 "invalid-number" "a number cannot be read or is not finite";
    E0104 "invalid-string" "a string has an unknown escape or no closing quote";
    E0105 "missing-unit" "a length or angle is written without its unit";
    E0106 "wrong-unit" "a value carries a unit of the wrong kind";
    E0107 "nesting-too-deep" "blocks are nested deeper than holoc reads";

    E0201 "unknown-object" "a reference names no object of the room";
    E0202 "unknown-room" "a reference names no room";
    E0203 "duplicate-definition" "two definitions use the same name";
    E0205 "constraint-cycle" "constraints refer to each other in a circle";
    E0206 "self-reference" "an object's constraint targets the object itself";
    E0207 "wrong-target-kind" "a reference names something of the wrong kind";
    E0208 "value-out-of-range" "a number is outside what the value allows";
    E0209 "multiple-global-constraints" "an object has more than one of `edge` and `middle`";
    E0210 "door-to-itself" "a door connects a room to itself";
    E0211 "unknown-keyword" "a word is not in the vocabulary of its position";
    E0212 "ambiguous-reference" "a reference names a group of several instances";
    E0213 "duplicate-setting" "a setting is given twice in one block";
    E0214 "too-few-corners" "a room outline has fewer than four corners";
    E0215 "multiple-scene-blocks" "a file has more than one `scene` block";
    E0216 "duplicate-connection" "two doors join the same pair of rooms";
    E0217 "misplaced-statement" "a statement is not allowed in this kind of block";
    E0218 "missing-target" "a relation names no object to relate to";
    E0219 "unexpected-target" "`edge` or `middle` is followed by an object name";
    E0220 "too-many-corners" "a room outline has more corners than holoc accepts";
    W0201 "window-size-not-offered" "a window size is not one of the sizes of its type";
    W0202 "missing-global-constraint" "a floor object has neither `edge` nor `middle`";
    W0203 "empty-scene" "the scene declares no room";

    E0301 "invalid-outline" "a room outline has a side that is not parallel to an axis, or no area";
    E0302 "self-intersecting-outline" "a room outline crosses or touches itself";
    E0303 "room-too-small" "a room is narrower than the smallest allowed room";
    E0304 "room-too-large" "a room is wider than the largest allowed room";
    E0305 "rooms-overlap" "two rooms cover the same floor";
    E0306 "room-inside-room" "a room lies entirely inside another room";
    E0307 "isolated-room" "a room shares no wall with any other room";
    E0308 "disconnected-plan" "the rooms form separate groups that share no wall";
    E0309 "rooms-not-adjacent" "a door or open connection joins rooms that share no wall";
    E0310 "door-does-not-fit" "no wall between the rooms is long enough for the door";
    E0311 "wall-already-has-hole" "every candidate wall already has a door or window";
    E0312 "open-to-exterior" "an open connection names the exterior";
    E0313 "unknown-door-asset" "a pinned door asset is not a door of the catalog";
    E0314 "no-exterior-door" "no door leads outside";
    E0315 "unreachable-room" "a room cannot be reached from outside through doors";
    E0316 "no-outside-wall" "a window names a side of the room that has no outside wall";
    E0317 "window-does-not-fit" "the windows of a row do not fit on their wall";
    E0318 "window-too-high" "a window's top is above the wall";
    E0319 "unknown-window-asset" "a pinned window asset is not a window of the catalog";
    E0320 "unknown-material" "a pinned material is not in the material database";
    W0301 "corner-snapped" "a corner nearly met another room's corner and was moved onto it";
    W0302 "door-added" "a doorway was added so that every room can be reached";
    W0303 "layer-conflict" "two neighbouring rooms had to share a lighting layer";
    W0304 "windows-fitted" "windows that do not fit their wall were narrowed or fewer were written";
    W0305 "sill-lowered" "a window's sill was lowered so that its top stays under the wall's margin";
    W0306 "door-dropped" "a door between rooms that does not fit is left out, every room being reachable without it";
    W0307 "plan-repaired" "room corners were moved, as little as possible, so that the floor plan builds";
    W0308 "rooms-gap" "two rooms face each other across a gap narrower than the repair's bound";
    W0309 "repair-work-bound" "the floor-plan repair stopped at its bound on work";

    E0601 "invalid-house-json" "a house file is not JSON or does not follow the house schema";
    E0602 "duplicate-id" "two entities of a house share an id";
    E0603 "unknown-reference" "a house entity refers to an id that does not exist";
    E0604 "hole-outside-wall" "a door or window hole is not inside its wall";
    E0605 "several-holes-in-wall" "a wall has more than one door or window hole";
    E0606 "room-not-closed" "a room's floor polygon is not a closed outline with an area";
    E0607 "object-outside-room" "an object stands outside every room";
    E0610 "schema-version" "a house's `metadata.schema` is missing or not the version AI2-THOR reads";
    E0611 "material-not-object" "a material of a house is a plain string instead of an object";
    E0612 "unknown-material" "a material name of a house is not an AI2-THOR material";
    E0613 "unknown-skybox" "a house's skybox is not an AI2-THOR skybox";
    E0614 "unknown-house-asset" "a door, window or object of a house uses an asset AI2-THOR does not have";
    W0610 "exterior-door-facing-out" "a door to the outside is written from the outside";
    W0611 "object-sunk" "an object's bottom is under the floor";
    W0612 "item-not-resting" "an item nested on a receptacle does not rest on its top";
    W0613 "agent-in-furniture" "the agent starts inside or against a floor object";
    E0615 "objathor-asset-missing" "a chosen objathor asset is not in the folder's `assets/`";
    E0616 "house-not-drawable" "a house lacks a member that `export` and `view` need and AI2-THOR has no default for";
    W0614 "objathor-assets-fetched" "the objathor folder has no `assets/`: the assets are fetched when the house loads";
    W0608 "objects-overlap" "the footprints of two floor objects overlap";
    W0609 "object-crosses-wall" "a floor object's footprint reaches through a wall of its room";
    E0401 "unknown-asset" "a pinned asset id is in no catalog";
    E0402 "asset-kind-mismatch" "a pinned asset cannot be placed the way the object is";
    E0403 "invalid-catalog" "a catalog file cannot be read or is not a catalog";
    W0401 "no-matching-asset" "no catalog asset matches an object well enough";
    W0402 "invalid-catalog-entry" "a catalog entry is malformed and is skipped";
    W0403 "stand-in-asset" "an asset of another type that does the same job stands in for a thing the catalog lacks";
    W0404 "placed-otherwise" "an object is placed in a way its catalog type does not list, as people place such things";
    E0404 "unusable-objathor-folder" "the folder given with `--objathor` is not an objathor version folder or base";
    E0405 "scoring-mode-unavailable" "the objathor scoring mode asked cannot run with this folder or build";
    W0405 "unusable-features" "an objathor feature file is missing or cannot be read, and is not used";
    W0406 "unlicensed-asset" "an objathor asset chosen for the house has no licence information";
    W0407 "objathor-index-unwritten" "the index of the objathor folder could not be written, so every build reads the folder again";
    E0406 "clip-weights-not-given" "the objathor scoring mode `clip` was asked without the CLIP text tower's weights";
    E0407 "unusable-clip-weights" "the CLIP text tower's weights or config cannot be read or are not a CLIP text model";
    E0408 "unusable-clip-tokenizer" "the CLIP tokenizer's files are missing, unreadable or not a CLIP vocabulary";
    E0409 "clip-dimension-mismatch" "the CLIP text tower's embeddings are not of the length of the folder's CLIP rows";
    W0408 "clip-tower-unused" "CLIP text tower weights were given but the scoring mode asked does not use them";
    E0701 "unreadable-line" "a line of an answer does not have the shape its stage expects";
    E0702 "invalid-value" "a field of an answer holds a value that cannot be used";
    E0703 "unknown-answer-room" "an answer names a room the floor plan does not have";
    E0704 "unknown-answer-object" "an answer names an object the room does not have";
    E0705 "unknown-answer-keyword" "an answer uses a word outside its vocabulary and synonym table";
    E0706 "invalid-answer-json" "an answer holds no usable JSON value";
    E0707 "dropped-constraint" "a constraint names an unknown object or the object itself";
    E0708 "empty-answer" "an answer holds nothing the stage can use";
    E0709 "invalid-transcript" "a transcript or scene file cannot be read";
    W0701 "tolerated-noise" "an answer had decoration that was removed";
    W0702 "synonym-used" "a near-miss keyword was read as its documented synonym";
    W0703 "converted-value" "a value with a unit or a decimal comma was converted";
    W0704 "renamed-duplicate" "a duplicate name was given a numbered id";
    W0705 "no-constraints" "a floor object has no constraints and will be placed at an edge";
    W0706 "ignored-input" "a line or field was ignored or replaced";
    W0707 "adjusted-value" "a value was clamped or defaulted";
    W0708 "circular-constraint" "a constraint naming a later line closes a circle of relations and is dropped";
    E0501 "unusable-room-outline" "a room's outline is not a rectilinear polygon the solver can use";
    E0502 "unusable-object" "an object's size, height or reference cannot be used by the solver";
    W0501 "unplaceable-object" "an object cannot be placed without breaking a hard rule and is left out";
    W0502 "pinned-pose-breaks-rule" "a pinned pose breaks a hard layout rule and is kept as pinned";
    W0503 "dependent-left-out" "an object whose every relation names an object left out is left out too";
    W0504 "room-object-limit" "a room has more floor objects than the solver places, and the rest are left out";
    W0505 "relation-given-up" "a relation names an object that is left out; the object stays and the relation is given up";
    W0506 "item-moved-to-allowed-receptacle" "a thing declared on a receptacle that does not take it is put on the nearest one that does, or left out";
    E0801 "unknown-placeholder" "a prompt template uses a placeholder its stage does not fill in";
    E0802 "missing-placeholder" "a prompt template leaves out a placeholder its answer depends on";
    E0803 "model-unauthorized" "the model server refused the API key";
    E0804 "model-not-found" "the model server does not know the address or the model";
    E0805 "model-unreachable" "the model server could not be reached";
    E0806 "model-timeout" "the model server did not answer in time";
    E0807 "model-server-error" "the model server kept failing after every retry";
    E0808 "invalid-model-response" "the model server's reply is not a chat completion";
    E0809 "unrepaired-answer" "an answer still has errors after every repair round";
    E0810 "replay-answer-missing" "the replayed transcript has no answer for a question";
    W0801 "answer-repaired" "an answer had errors and a repair round fixed it";
    E0811 "batch-incomplete" "a manifest line is in no shard's summary, or is not done, so the merged summary would not cover the manifest";
    E0812 "empty-scene" "a batch job's scene declares no room";
    W0802 "generation-field-ignored" "a build line of a batch manifest names a field only generate jobs use, and it is ignored";
}

impl Code {
    /// The default severity: `E` codes are errors, `W` codes warnings.
    pub fn severity(self) -> Severity {
        if self.as_str().starts_with('W') {
            Severity::Warning
        } else {
            Severity::Error
        }
    }

    /// The stage that emits the code, from its band.
    pub fn stage(self) -> &'static str {
        match &self.as_str()[1..3] {
            "00" => "driver",
            "01" => "parse",
            "02" => "check",
            "03" => "plan",
            "04" => "resolve",
            "05" => "solve",
            "06" => "lower",
            "07" => "import",
            "08" => "generate",
            _ => "unknown",
        }
    }

    /// Where the code's page is: its path in the book's sources (`holoc explain CODE` prints
    /// the same page). holoc has no published web address, so none is made up here.
    pub fn url(self) -> String {
        format!("book/src/diagnostics/{}.md", self.as_str())
    }

    /// Looks a code up by its text (`E0201`, case-insensitive) or its name (`unknown-object`).
    pub fn parse(text: &str) -> Option<Code> {
        let text = text.trim();
        Code::ALL
            .iter()
            .copied()
            .find(|c| c.as_str().eq_ignore_ascii_case(text) || c.name().eq_ignore_ascii_case(text))
    }
}
