//! An instance checked against its type as the server serves the type
//! model (the loaded NodeSets): every InstanceDeclaration of the type, its
//! supertypes and interfaces whose modelling rule is Mandatory must exist
//! in the instance with the same BrowseName and NodeClass and a
//! TypeDefinition that is the declared one or a subtype; a
//! MandatoryPlaceholder needs at least one member of its type. Members
//! found are checked the same way, down the whole instance; a member no
//! declaration names is checked against its own type. Only browsing:
//! nothing here knows which nodes a type declares.

use std::collections::{HashMap, HashSet};
use std::future::Future;
use std::pin::Pin;

use opcua::types::{
    BrowseDirection, NodeClass, NodeId, ObjectId, QualifiedName, ReferenceDescription,
    ReferenceTypeId,
};

use super::Ua;

/// HasInterface (OPC 10000-3, 7.22): not every library names it.
const HAS_INTERFACE: u32 = 17603;

/// An InstanceDeclaration as browsed.
#[derive(Debug, Clone)]
struct Decl {
    name: QualifiedName,
    node: NodeId,
    class: NodeClass,
    type_def: NodeId,
    rule: Rule,
}

/// A declaration's modelling rule.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Rule {
    Mandatory,
    Optional,
    MandatoryPlaceholder,
    OptionalPlaceholder,
    None,
}

/// What a walk found.
#[derive(Debug, Default)]
pub struct Report {
    /// Every instance node checked against a declaration, by path.
    pub checked: Vec<String>,
    /// What does not conform, by path.
    pub problems: Vec<String>,
}

/// A walk through an instance.
pub struct Walk<'a> {
    ua: &'a Ua,
    report: Report,
    supertypes: HashMap<NodeId, Option<NodeId>>,
    seen: HashSet<NodeId>,
}

type Boxed<'b, T> = Pin<Box<dyn Future<Output = T> + 'b>>;

impl<'a> Walk<'a> {
    /// Checks `instance` (named `path`) against its type definition.
    pub async fn check(ua: &'a Ua, instance: &NodeId, path: &str) -> Report {
        let ty = Self::type_of(ua, instance).await;
        Self::check_as(ua, instance, path, &ty).await
    }

    /// Checks `instance` (named `path`) against type `ty`.
    pub async fn check_as(ua: &'a Ua, instance: &NodeId, path: &str, ty: &NodeId) -> Report {
        let mut walk = Walk {
            ua,
            report: Report::default(),
            supertypes: HashMap::new(),
            seen: HashSet::new(),
        };
        walk.node(instance.clone(), path.to_owned(), ty.clone(), None)
            .await;
        walk.report
    }

    /// The TypeDefinition of an object or variable.
    pub async fn type_of(ua: &Ua, node: &NodeId) -> NodeId {
        let r = ua
            .browse(
                node,
                ReferenceTypeId::HasTypeDefinition,
                BrowseDirection::Forward,
            )
            .await;
        r.first()
            .map(|r| r.node_id.node_id.clone())
            .unwrap_or_default()
    }

    /// The supertype of a type (cached).
    async fn supertype(&mut self, ty: &NodeId) -> Option<NodeId> {
        if let Some(s) = self.supertypes.get(ty) {
            return s.clone();
        }
        let up = self
            .ua
            .browse(ty, ReferenceTypeId::HasSubtype, BrowseDirection::Inverse)
            .await
            .first()
            .map(|r| r.node_id.node_id.clone());
        self.supertypes.insert(ty.clone(), up.clone());
        up
    }

    /// Whether `ty` is `ancestor` or one of its subtypes.
    async fn is_subtype(&mut self, ty: &NodeId, ancestor: &NodeId) -> bool {
        let mut at = Some(ty.clone());
        while let Some(t) = at {
            if t == *ancestor {
                return true;
            }
            at = self.supertype(&t).await;
        }
        false
    }

    /// The members declared right below `node`.
    async fn children(&self, node: &NodeId) -> Vec<Decl> {
        let mut out = Vec::new();
        let refs = self
            .ua
            .browse(
                node,
                ReferenceTypeId::HierarchicalReferences,
                BrowseDirection::Forward,
            )
            .await;
        for r in refs {
            if r.reference_type_id == ReferenceTypeId::HasSubtype {
                continue;
            }
            let rule = self.rule(&r.node_id.node_id).await;
            out.push(decl(r, rule));
        }
        out
    }

    /// A declaration's modelling rule.
    async fn rule(&self, node: &NodeId) -> Rule {
        let r = self
            .ua
            .browse(
                node,
                ReferenceTypeId::HasModellingRule,
                BrowseDirection::Forward,
            )
            .await;
        let Some(r) = r.first() else {
            return Rule::None;
        };
        let id = &r.node_id.node_id;
        if *id == ObjectId::ModellingRule_Mandatory {
            Rule::Mandatory
        } else if *id == ObjectId::ModellingRule_Optional {
            Rule::Optional
        } else if *id == ObjectId::ModellingRule_MandatoryPlaceholder {
            Rule::MandatoryPlaceholder
        } else if *id == ObjectId::ModellingRule_OptionalPlaceholder {
            Rule::OptionalPlaceholder
        } else {
            Rule::None
        }
    }

    /// The InstanceDeclarations of `ty`: of its supertypes and
    /// interfaces first, replaced by a more derived one of the same name.
    fn declarations<'b>(&'b mut self, ty: NodeId) -> Boxed<'b, Vec<Decl>> {
        Box::pin(async move {
            let mut chain = vec![ty.clone()];
            let mut at = ty;
            while let Some(up) = self.supertype(&at).await {
                chain.push(up.clone());
                at = up;
            }
            let mut out: Vec<Decl> = Vec::new();
            for t in chain.into_iter().rev() {
                let interfaces = self
                    .ua
                    .browse(&t, NodeId::new(0, HAS_INTERFACE), BrowseDirection::Forward)
                    .await;
                let mut layer = Vec::new();
                for i in interfaces {
                    layer.extend(self.declarations(i.node_id.node_id).await);
                }
                layer.extend(self.children(&t).await);
                for d in layer {
                    out.retain(|o| o.name != d.name);
                    out.push(d);
                }
            }
            out
        })
    }

    /// Checks the node `inst` at `path` as an instance of `ty` declared by
    /// `decl` (whose own members add to or replace the type's).
    fn node<'b>(
        &'b mut self,
        inst: NodeId,
        path: String,
        ty: NodeId,
        decl: Option<NodeId>,
    ) -> Boxed<'b, ()> {
        Box::pin(async move {
            if !self.seen.insert(inst.clone()) {
                return;
            }
            let mut members = self.declarations(ty).await;
            if let Some(d) = decl {
                for own in self.children(&d).await {
                    members.retain(|m| m.name != own.name);
                    members.push(own);
                }
            }
            let kids = self
                .ua
                .browse(
                    &inst,
                    ReferenceTypeId::HierarchicalReferences,
                    BrowseDirection::Forward,
                )
                .await;
            let named: HashSet<&QualifiedName> = members.iter().map(|m| &m.name).collect();
            let mut visits = Vec::new();
            for m in &members {
                match m.rule {
                    Rule::Mandatory | Rule::Optional => {
                        match kids.iter().find(|k| k.browse_name == m.name) {
                            Some(k) => visits.push((k.clone(), m.clone())),
                            None if m.rule == Rule::Mandatory => self
                                .report
                                .problems
                                .push(format!("{path}/{}: missing", m.name.name)),
                            None => {}
                        }
                    }
                    Rule::MandatoryPlaceholder | Rule::OptionalPlaceholder => {
                        let mut found = 0;
                        for k in kids.iter().filter(|k| !named.contains(&k.browse_name)) {
                            if k.node_class == m.class
                                && self
                                    .is_subtype(&k.type_definition.node_id, &m.type_def)
                                    .await
                            {
                                found += 1;
                                visits.push((k.clone(), m.clone()));
                            }
                        }
                        if found == 0 && m.rule == Rule::MandatoryPlaceholder {
                            self.report
                                .problems
                                .push(format!("{path}/{}: no member", m.name.name));
                        }
                    }
                    Rule::None => {}
                }
            }
            // Members of the server's own (no declaration names them) are
            // instances of their own types, and checked as such.
            let declared: HashSet<NodeId> = visits
                .iter()
                .map(|(k, _)| k.node_id.node_id.clone())
                .collect();
            let own: Vec<ReferenceDescription> = kids
                .iter()
                .filter(|k| !declared.contains(&k.node_id.node_id))
                .filter(|k| matches!(k.node_class, NodeClass::Object | NodeClass::Variable))
                .cloned()
                .collect();
            for (k, m) in visits {
                self.member(&path, k, m).await;
            }
            for k in own {
                let at = format!("{path}/{}", k.browse_name.name);
                let ty = k.type_definition.node_id.clone();
                self.node(k.node_id.node_id, at, ty, None).await;
            }
        })
    }

    /// Checks one member `k` of the node at `path` against `m`.
    async fn member(&mut self, path: &str, k: ReferenceDescription, m: Decl) {
        let at = format!("{path}/{}", k.browse_name.name);
        let ty = k.type_definition.node_id.clone();
        if k.node_class != m.class {
            self.report.problems.push(format!(
                "{at}: a {:?}, declared a {:?}",
                k.node_class, m.class
            ));
        } else if matches!(m.class, NodeClass::Object | NodeClass::Variable)
            && !self.is_subtype(&ty, &m.type_def).await
        {
            self.report
                .problems
                .push(format!("{at}: of type {ty}, declared {}", m.type_def));
        }
        self.report.checked.push(at.clone());
        if matches!(k.node_class, NodeClass::Object | NodeClass::Variable) {
            self.node(k.node_id.node_id, at, ty, Some(m.node)).await;
        }
    }
}

/// A browsed reference as a declaration.
fn decl(r: ReferenceDescription, rule: Rule) -> Decl {
    Decl {
        name: r.browse_name,
        node: r.node_id.node_id,
        class: r.node_class,
        type_def: r.type_definition.node_id,
        rule,
    }
}
