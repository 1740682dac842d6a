//! The address space planned from a [`Table`]: the folders and variables
//! with their NodeId strings, names, descriptions, types and access, and
//! where each variable's value comes from. No value is kept here: a
//! variable only knows which object (or reading) to ask.
//!
//! NodeIds are strings in the face's namespace: `1300` (the bus folder),
//! `1300/1` (a device), `1300/1/2` (an instance folder: group 2),
//! `1300/1/2/6` (the object at that address), `dashboard` and the
//! readings' own ids.

use uoi::{Access, ObjectAddress, ValueRange, ValueType};

use crate::layout::{IndexKind, Table};

/// Where a folder sits.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) enum Parent {
    /// The standard Objects folder.
    Objects,
    /// A folder of the face (its NodeId string).
    Folder(String),
}

/// A folder of the face.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Folder {
    pub id: String,
    pub parent: Parent,
    pub name: String,
    pub doc: String,
}

/// Where a variable's value comes from.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum Source {
    /// An object of the table.
    Object(ObjectAddress, ValueType),
    /// A reading of the table (its position in `Table::readings`).
    Reading(usize),
}

/// A variable of the face.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Var {
    pub id: String,
    /// The NodeId string of its folder.
    pub parent: String,
    pub name: String,
    pub doc: String,
    pub ty: ValueType,
    pub access: Access,
    /// Lowest and highest value a write may carry, where the range is one
    /// interval.
    pub range: Option<(f64, f64)>,
    pub source: Source,
}

/// Every folder and variable of the face, parents before children.
#[derive(Debug, Clone, Default)]
pub(crate) struct Plan {
    pub folders: Vec<Folder>,
    pub vars: Vec<Var>,
    /// The NodeId strings of folders and variables in the order they were
    /// planned: the order a browse lists them in.
    pub order: Vec<String>,
}

impl Plan {
    fn folder(&mut self, folder: Folder) {
        self.order.push(folder.id.clone());
        self.folders.push(folder);
    }

    fn var(&mut self, var: Var) {
        self.order.push(var.id.clone());
        self.vars.push(var);
    }
}

/// The NodeId string of the dashboard folder.
pub(crate) const DASHBOARD: &str = "dashboard";

/// The address space of `table`.
pub(crate) fn plan(table: &Table) -> Plan {
    let mut plan = Plan::default();
    let bus = table.bus.to_string();
    plan.folder(Folder {
        id: bus.clone(),
        parent: Parent::Objects,
        name: format!("Bus{bus}"),
        doc: format!("UOI bus {bus}: its objects by device, and a dashboard"),
    });
    for device in &table.devices {
        plan_device(&mut plan, table, device.number);
    }
    plan_dashboard(&mut plan, table);
    plan
}

/// The folder of `number`, its instance folders, and its objects.
fn plan_device(plan: &mut Plan, table: &Table, number: u16) {
    let Some(device) = table.devices.iter().find(|d| d.number == number) else {
        return;
    };
    let id = format!("{}/{number}", table.bus);
    plan.folder(Folder {
        id: id.clone(),
        parent: Parent::Folder(table.bus.to_string()),
        name: format!("Device{number}"),
        doc: device.title.clone(),
    });
    let rows: Vec<_> = table.rows.iter().filter(|r| r.device == number).collect();
    let mut indexes: Vec<u16> = rows.iter().flat_map(|r| r.index.clone()).collect();
    indexes.sort_unstable();
    indexes.dedup();
    for index in indexes {
        let folder = match &device.index {
            IndexKind::Object => id.clone(),
            IndexKind::Instance { name, note } => {
                let folder = format!("{id}/{index}");
                plan.folder(Folder {
                    id: folder.clone(),
                    parent: Parent::Folder(id.clone()),
                    name: format!("{name}{index}"),
                    doc: note.replace("{}", &index.to_string()),
                });
                folder
            }
        };
        for row in rows.iter().filter(|r| r.index.contains(&index)) {
            for sub in row.sub.clone() {
                let addr = ObjectAddress::new(table.bus, number, index, sub);
                let many = row.sub.start() != row.sub.end();
                let name = if many {
                    format!("{}[{}]", row.name, sub - row.sub.start())
                } else {
                    row.name.clone()
                };
                plan.var(Var {
                    id: addr.to_string(),
                    parent: folder.clone(),
                    name,
                    doc: object_doc(addr, row.ty, row.access, row.range, &row.doc),
                    ty: row.ty,
                    access: row.access,
                    range: row.access.writable().then(|| interval(row.range)).flatten(),
                    source: Source::Object(addr, row.ty),
                });
            }
        }
    }
}

/// `1300/1/2/6 (d, rw, -1e9..=1e9): Tool radius ...`
fn object_doc(
    addr: ObjectAddress,
    ty: ValueType,
    access: Access,
    range: ValueRange,
    doc: &str,
) -> String {
    if access.writable() {
        format!("{addr} ({ty}, {access}, {range}): {doc}")
    } else {
        format!("{addr} ({ty}, {access}): {doc}")
    }
}

/// The range as one interval, where it is one.
fn interval(range: ValueRange) -> Option<(f64, f64)> {
    match range {
        ValueRange::Int { min, max } => Some((f64::from(min), f64::from(max))),
        ValueRange::Finite { min, max } => Some((min, max)),
        ValueRange::AnyInt | ValueRange::IntSet(_) | ValueRange::AnyFinite => None,
    }
}

/// The dashboard folder, its subfolders and its readings.
fn plan_dashboard(plan: &mut Plan, table: &Table) {
    if table.readings.is_empty() {
        return;
    }
    plan.folder(Folder {
        id: DASHBOARD.into(),
        parent: Parent::Folder(table.bus.to_string()),
        name: "Dashboard".into(),
        doc: "Read-only values to watch: executed position, spooler queue, the groups' STATUS and ERROR".into(),
    });
    for (i, reading) in table.readings.iter().enumerate() {
        let mut parent = DASHBOARD.to_string();
        for folder in &reading.path {
            let id = format!("{parent}/{folder}");
            if !plan.folders.iter().any(|f| f.id == id) {
                plan.folder(Folder {
                    id: id.clone(),
                    parent: Parent::Folder(parent.clone()),
                    name: folder.clone(),
                    doc: String::new(),
                });
            }
            parent = id;
        }
        plan.var(Var {
            id: reading.id.clone(),
            parent,
            name: reading.name.clone(),
            doc: reading.doc.clone(),
            ty: reading.ty,
            access: Access::ReadOnly,
            range: None,
            source: Source::Reading(i),
        });
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::layout::{Device, Reading, Row};
    use std::sync::Arc;
    use uoi::wire::Request;

    fn table() -> Table {
        let row = |name: &str, device, index, sub, access, range| Row {
            name: name.into(),
            doc: format!("{name} doc"),
            device,
            index,
            sub,
            ty: ValueType::I32,
            access,
            range,
        };
        Table {
            bus: 7,
            devices: vec![
                Device {
                    number: 0,
                    title: "globals".into(),
                    index: IndexKind::Object,
                },
                Device {
                    number: 1,
                    title: "groups".into(),
                    index: IndexKind::Instance {
                        name: "Group".into(),
                        note: "group {}".into(),
                    },
                },
            ],
            rows: vec![
                row(
                    "Axes",
                    0,
                    2..=2,
                    0..=2,
                    Access::ReadWrite,
                    ValueRange::Int { min: 0, max: 7 },
                ),
                row("Go", 0, 3..=3, 0..=0, Access::WriteOnly, ValueRange::AnyInt),
                row(
                    "State",
                    1,
                    1..=2,
                    3..=3,
                    Access::ReadOnly,
                    ValueRange::Int { min: 0, max: 1 },
                ),
            ],
            readings: vec![Reading {
                id: "dashboard/g1".into(),
                path: vec!["Group1".into()],
                name: "State".into(),
                doc: "the state".into(),
                ty: ValueType::I32,
                request: Request::Read(ObjectAddress::new(7, 1, 1, 3), ValueType::I32),
                pick: Arc::new(crate::layout::answer_value),
            }],
            machine: None,
        }
    }

    #[test]
    fn folders_per_device_and_instance_and_one_variable_per_subindex() {
        let plan = plan(&table());
        assert_eq!(plan.order[..4], ["7", "7/0", "7/0/2/0", "7/0/2/1"]);
        let folders: Vec<_> = plan
            .folders
            .iter()
            .map(|f| (f.id.as_str(), f.name.as_str()))
            .collect();
        assert_eq!(
            folders,
            [
                ("7", "Bus7"),
                ("7/0", "Device0"),
                ("7/1", "Device1"),
                ("7/1/1", "Group1"),
                ("7/1/2", "Group2"),
                ("dashboard", "Dashboard"),
                ("dashboard/Group1", "Group1"),
            ]
        );
        assert_eq!(plan.folders[3].doc, "group 1");
        let vars: Vec<_> = plan
            .vars
            .iter()
            .map(|v| (v.id.as_str(), v.parent.as_str(), v.name.as_str()))
            .collect();
        assert_eq!(
            vars,
            [
                ("7/0/2/0", "7/0", "Axes[0]"),
                ("7/0/2/1", "7/0", "Axes[1]"),
                ("7/0/2/2", "7/0", "Axes[2]"),
                ("7/0/3/0", "7/0", "Go"),
                ("7/1/1/3", "7/1/1", "State"),
                ("7/1/2/3", "7/1/2", "State"),
                ("dashboard/g1", "dashboard/Group1", "State"),
            ]
        );
    }

    #[test]
    fn descriptions_carry_address_type_access_and_the_writable_range() {
        let plan = plan(&table());
        assert_eq!(plan.vars[0].doc, "7/0/2/0 (i, rw, 0..=7): Axes doc");
        assert_eq!(plan.vars[0].range, Some((0.0, 7.0)));
        assert_eq!(plan.vars[3].doc, "7/0/3/0 (i, w, any): Go doc");
        assert_eq!(plan.vars[3].range, None);
        // A read-only object has no write range.
        assert_eq!(plan.vars[4].doc, "7/1/1/3 (i, r): State doc");
        assert_eq!(plan.vars[4].range, None);
        assert_eq!(plan.vars[6].access, Access::ReadOnly);
        assert_eq!(plan.vars[6].source, Source::Reading(0));
    }
}
