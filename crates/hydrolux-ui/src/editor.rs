//! The scene editor: the scene as its TOML table, one egui widget per value
//! (a collapsible section per table, one per `[[objects]]` entry, a combo
//! box for every enumerated key), re-parsed into a [`Scene`] on each edit so
//! that bad values are refused with the scene loader's own message.

use egui::Ui;
use hydrolux_core::scene::{Scene, enumerated_keys};
use toml::{Table, Value};

pub struct SceneEditor {
    pub table: Table,
    /// The table as loaded: what the person has not changed.
    loaded: Table,
    /// Relative mesh and texture paths start at the scene file's folder.
    base_dir: std::path::PathBuf,
    /// Why the last edit was refused, if it was.
    pub error: Option<String>,
    /// What the last accepted edit left without effect (`check_effective`).
    pub warning: Option<String>,
}

impl SceneEditor {
    pub fn new(scene: &Scene) -> Self {
        let table = scene.to_table();
        SceneEditor {
            loaded: table.clone(),
            table,
            base_dir: scene.base_dir.clone(),
            error: None,
            warning: None,
        }
    }

    /// The scene the table describes now. What the loader would refuse
    /// only because the table shows it is left out: a named medium's
    /// coefficients (`water.absorption`, `water.scattering`, shown for
    /// reference) unless the person changed them (choosing another medium
    /// must bring that medium's own), and an object's empty `mesh` (it
    /// stands for "the primitive").
    pub fn scene(&self) -> Result<Scene, String> {
        let mut table = self.table.clone();
        if let Some(Value::Array(objects)) = table.get_mut("objects") {
            for o in objects.iter_mut().filter_map(Value::as_table_mut) {
                if o.get("mesh").and_then(Value::as_str) == Some("") {
                    o.remove("mesh");
                }
            }
        }
        if let Some(Value::Table(water)) = table.get_mut("water")
            && water.get("medium").and_then(Value::as_str).is_some_and(|m| m != "custom")
        {
            for key in ["absorption", "scattering"] {
                let loaded = self.loaded.get("water").and_then(|w| w.get(key));
                if water.get(key) == loaded {
                    water.remove(key);
                }
            }
        }
        let mut s =
            Scene::from_toml_live(&table.to_string(), "editor", &[]).map_err(|e| e.to_string())?;
        s.base_dir = self.base_dir.clone();
        Ok(s)
    }

    /// Every section, collapsible (those that shape what the scene shows
    /// open: the sun, the water, and the waves its model draws); true if
    /// a value changed.
    pub fn sections_ui(&mut self, ui: &mut Ui) -> bool {
        let open_sections = self.open_sections();
        let mut changed = false;
        egui::ScrollArea::vertical().show(ui, |ui| {
            for (section, value) in self.table.iter_mut() {
                let open = open_sections.contains(&section.as_str());
                changed |= edit_entry(ui, section, section, section, value, open);
            }
        });
        changed
    }

    /// The sections that open at first: `sun`, `water`, and the one that
    /// makes the waves (`ocean` for fft, `sines`, `ripples` for the
    /// interactive water).
    pub fn open_sections(&self) -> Vec<&'static str> {
        let water = self.table.get("water");
        let model = water.and_then(|w| w.get("model")).and_then(Value::as_str).unwrap_or("fft");
        let dynamic = water.and_then(|w| w.get("dynamic")).and_then(Value::as_bool) == Some(true);
        let mut open = vec!["sun", "water"];
        match model {
            "fft" => open.push("ocean"),
            "sines" => open.push("sines"),
            _ => {}
        }
        if dynamic {
            open.push("ripples");
        }
        // A scene with the volumetric liquid: its domain, grid and sources.
        let fluid = self.table.get("fluid").and_then(|f| f.get("sources"));
        if fluid.and_then(Value::as_array).is_some_and(|s| !s.is_empty()) {
            open.push("fluid");
        }
        open
    }

    /// The edit was taken and gave `scene`: show what it resolved to where
    /// the table holds derived values (a named medium's coefficients, which
    /// otherwise kept showing the previous medium's numbers).
    pub fn accepted(&mut self, scene: &Scene) {
        // A switch flipped live may leave settings without effect: say so
        // (a file or --set with them is refused).
        self.warning = scene.check_effective().err().map(|e| e.to_string());
        let named = self.get("water", "medium").is_some_and(|m| m != "custom");
        if !named {
            return;
        }
        let resolved = scene.to_table();
        for key in ["absorption", "scattering"] {
            let Some(v) = resolved.get("water").and_then(|w| w.get(key)).cloned() else {
                continue;
            };
            for table in [&mut self.table, &mut self.loaded] {
                if let Some(Value::Table(w)) = table.get_mut("water") {
                    w.insert(key.into(), v.clone());
                }
            }
        }
    }

    /// A line that says why the scene looks as it does after an edit whose
    /// effect surprises (`water.model = "fft"` draws the `[ocean]` section's
    /// sea, whatever the scene is), or `None`.
    pub fn hint(&self, scene: &Scene) -> Option<String> {
        use hydrolux_core::scene::WaterModel;
        (scene.water.model == WaterModel::Fft && self.loaded_model() != Some("fft")).then(|| {
            format!(
                "water.model = fft draws the [ocean] section's sea: wind {:.1} m/s \
                 (ocean.wind_speed), waves of up to {:.1} m significant height when fully \
                 developed; lower the wind for calm water",
                scene.ocean.wind_speed,
                // Pierson–Moskowitz: Hs = 0.21·U²/g.
                0.21 * scene.ocean.wind_speed * scene.ocean.wind_speed / 9.81
            )
        })
    }

    fn loaded_model(&self) -> Option<&str> {
        self.loaded.get("water")?.get("model")?.as_str()
    }

    /// The string value of `section.key`, if set.
    pub fn get(&self, section: &str, key: &str) -> Option<&str> {
        self.table.get(section)?.get(key)?.as_str()
    }

    /// Set `section.key` to the string `value`.
    pub fn set(&mut self, section: &str, key: &str, value: &str) {
        let table = self.table.entry(section).or_insert_with(|| Value::Table(Default::default()));
        if let Value::Table(r) = table {
            r.insert(key.into(), Value::String(value.into()));
        }
    }

    /// Step `section.key` to the next of `names` (V: the debug view, G: the
    /// god-ray method); the new value.
    pub fn cycle(&mut self, section: &str, key: &str, names: &[String]) -> String {
        let current = self.get(section, key).unwrap_or(&names[0]).to_string();
        let i = names.iter().position(|n| *n == current).unwrap_or(0);
        let next = names[(i + 1) % names.len()].clone();
        self.set(section, key, &next);
        next
    }

    /// The choices a person flips most (debug view, god-ray and caustics
    /// methods) and the last edit's error; true if a choice changed.
    pub fn choices_ui(&mut self, ui: &mut Ui) -> bool {
        use hydrolux_core::scene::{CausticMethod, Choice, DebugView, GodRayMethod};
        let mut changed = self.choice_ui(ui, "view", "render", "view", &DebugView::names());
        changed |= self.choice_ui(ui, "god rays", "godrays", "method", &GodRayMethod::names());
        changed |= self.choice_ui(ui, "caustics", "caustics", "method", &CausticMethod::names());
        if let Some(e) = &self.error {
            ui.colored_label(egui::Color32::from_rgb(255, 110, 110), e);
        } else if let Some(w) = &self.warning {
            ui.colored_label(egui::Color32::from_rgb(255, 200, 90), w);
        }
        changed
    }

    /// A combo box for `section.key` over `names`; true if it changed.
    pub fn choice_ui(
        &mut self,
        ui: &mut Ui,
        label: &str,
        section: &str,
        key: &str,
        names: &[String],
    ) -> bool {
        let mut value = self.get(section, key).unwrap_or(&names[0]).to_string();
        let mut changed = false;
        ui.horizontal(|ui| {
            ui.label(label);
            egui::ComboBox::from_id_salt(format!("choice.{section}.{key}"))
                .selected_text(value.as_str())
                .show_ui(ui, |ui| {
                    for n in names {
                        changed |= ui.selectable_value(&mut value, n.clone(), n).changed();
                    }
                });
        });
        if changed {
            self.set(section, key, &value);
        }
        changed
    }
}

/// A table becomes a collapsible section, an array of tables (`[[objects]]`)
/// one section per entry, anything else one widget. `id` is unique per
/// widget; `kind` is the key path without array indices (for the enum list).
fn edit_entry(
    ui: &mut Ui,
    id: &str,
    kind: &str,
    label: &str,
    value: &mut Value,
    open: bool,
) -> bool {
    let mut changed = false;
    match value {
        Value::Table(t) => {
            egui::CollapsingHeader::new(label).id_salt(id).default_open(open).show(ui, |ui| {
                for (key, v) in t.iter_mut() {
                    changed |= edit_entry(
                        ui,
                        &format!("{id}.{key}"),
                        &format!("{kind}.{key}"),
                        key,
                        v,
                        false,
                    );
                }
            });
        }
        Value::Array(items) if items.first().is_some_and(Value::is_table) => {
            egui::CollapsingHeader::new(label).id_salt(id).default_open(open).show(ui, |ui| {
                for (i, item) in items.iter_mut().enumerate() {
                    let name = item
                        .get("name")
                        .and_then(Value::as_str)
                        .filter(|n| !n.is_empty())
                        .map(str::to_string);
                    let title =
                        name.map_or(format!("{label}[{i}]"), |n| format!("{label}[{i}] {n}"));
                    changed |= edit_entry(ui, &format!("{id}[{i}]"), kind, &title, item, false);
                }
            });
        }
        _ => changed |= edit_value(ui, id, kind, label, value),
    }
    changed
}

/// One widget per TOML value; returns whether it changed.
fn edit_value(ui: &mut Ui, id: &str, path: &str, key: &str, value: &mut Value) -> bool {
    ui.horizontal(|ui| {
        ui.label(key);
        match value {
            Value::Float(f) => {
                let speed = (f.abs() * 0.01).max(0.01);
                ui.add(egui::DragValue::new(f).speed(speed)).changed()
            }
            Value::Integer(i) => ui.add(egui::DragValue::new(i).speed(1.0)).changed(),
            Value::Boolean(b) => ui.checkbox(b, "").changed(),
            Value::Array(a) => {
                let mut c = false;
                for v in a.iter_mut() {
                    if let Value::Float(f) = v {
                        c |= ui.add(egui::DragValue::new(f).speed(0.05)).changed();
                    }
                }
                c
            }
            Value::String(s) => {
                let keys = enumerated_keys();
                if let Some((_, options)) = keys.iter().find(|(p, _)| *p == path) {
                    let mut c = false;
                    egui::ComboBox::from_id_salt(id).selected_text(s.as_str()).show_ui(ui, |ui| {
                        for o in options {
                            c |= ui.selectable_value(s, o.clone(), o).changed();
                        }
                    });
                    c
                } else {
                    ui.text_edit_singleline(s).lost_focus()
                }
            }
            _ => false,
        }
    })
    .inner
}

#[cfg(test)]
mod tests {
    use super::*;
    use hydrolux_core::scene::{Choice, DebugView};

    #[test]
    fn the_liquid_s_section_opens_where_a_scene_has_one() {
        let open = |name: &str| SceneEditor::new(&Scene::load(name, &[]).unwrap()).open_sections();
        assert!(open("dam_break").contains(&"fluid"));
        assert!(open("pour").contains(&"fluid"));
        assert!(!open("pool").contains(&"fluid"));
    }

    #[test]
    fn every_builtin_scene_comes_back_unchanged_from_the_editor() {
        for b in hydrolux_core::scene::BUILTIN_SCENES {
            let scene = Scene::load(b.name, &[]).unwrap();
            let back =
                SceneEditor::new(&scene).scene().unwrap_or_else(|e| panic!("{}: {e}", b.name));
            let same =
                |s: &Scene| (s.water.clone(), s.objects.clone(), s.floor.clone(), s.sun.clone());
            assert!(
                same(&back) == same(&scene),
                "{} changed on its way through the editor",
                b.name
            );
        }
    }

    #[test]
    fn edits_round_trip_through_the_scene_loader() {
        let scene = Scene::load("pool", &[]).unwrap();
        let mut e = SceneEditor::new(&scene);
        let same = e.scene().unwrap();
        assert!(
            same.water == scene.water && same.objects == scene.objects && same.sun == scene.sun
        );
        let views = DebugView::names();
        assert_eq!(e.cycle("render", "view", &views), views[1]);
        assert_eq!(e.scene().unwrap().render.view.name(), views[1]);
        e.set("render", "view", "sideways");
        assert!(e.scene().unwrap_err().contains("render.view"));
        e.set("render", "view", "final");
        // Another named medium brings its own coefficients.
        e.set("water", "medium", "coastal");
        let coastal = Scene::load("pool", &["water.medium=\"coastal\"".into()]).unwrap();
        assert_eq!(e.scene().unwrap().water.absorption, coastal.water.absorption);
        // Changed coefficients with a named medium are the loader's error, said as such.
        if let Some(Value::Table(w)) = e.table.get_mut("water") {
            w.insert("absorption".into(), Value::Array(vec![Value::Float(0.5); 3]));
        }
        assert!(e.scene().unwrap_err().contains("water.absorption"));
    }
}
