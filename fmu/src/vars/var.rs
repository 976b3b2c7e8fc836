//! One scalar variable ([`Var`]) and what describes it: its FMI base type, causality,
//! variability and value.

use super::enums::EnumType;
use super::slot::Key;

/// FMI base type (how a value crosses the C API: Enumerations go through fmi2Get/SetInteger).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Type {
    /// fmi2Real.
    Real,
    /// fmi2Integer.
    Integer,
    /// fmi2Boolean.
    Boolean,
    /// fmi2String.
    String,
}

impl Type {
    /// Element name in the XML.
    pub fn xml(self) -> &'static str {
        match self {
            Type::Real => "Real",
            Type::Integer => "Integer",
            Type::Boolean => "Boolean",
            Type::String => "String",
        }
    }
}

/// FMI causality.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Causality {
    /// Set before initialisation, fixed afterwards.
    Parameter,
    /// Set by the master at communication points.
    Input,
    /// Computed.
    Output,
}

impl Causality {
    /// Attribute value.
    pub fn xml(self) -> &'static str {
        match self {
            Causality::Parameter => "parameter",
            Causality::Input => "input",
            Causality::Output => "output",
        }
    }
}

/// FMI variability.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Variability {
    /// Fixed after initialisation.
    Fixed,
    /// Changes only at communication points: Integer, Boolean, and Reals of a sampled-data system
    /// (the measurements and the estimate, which change only at measurement epochs).
    Discrete,
    /// Real quantity of a continuous process (the truth).
    Continuous,
}

impl Variability {
    /// Attribute value.
    pub fn xml(self) -> &'static str {
        match self {
            Variability::Fixed => "fixed",
            Variability::Discrete => "discrete",
            Variability::Continuous => "continuous",
        }
    }
}

/// A variable value.
#[derive(Debug, Clone, PartialEq)]
pub enum Value {
    /// Real.
    Real(f64),
    /// Integer (and Enumeration).
    Integer(i32),
    /// Boolean.
    Boolean(bool),
    /// String.
    String(String),
}

impl Value {
    /// The value's type.
    pub fn ty(&self) -> Type {
        match self {
            Value::Real(_) => Type::Real,
            Value::Integer(_) => Type::Integer,
            Value::Boolean(_) => Type::Boolean,
            Value::String(_) => Type::String,
        }
    }

    /// As written in a `start` attribute.
    pub fn xml(&self) -> String {
        match self {
            Value::Real(v) => format!("{v:?}"),
            Value::Integer(v) => v.to_string(),
            Value::Boolean(v) => v.to_string(),
            Value::String(s) => s.clone(),
        }
    }
}

/// One scalar variable.
#[derive(Debug, Clone, PartialEq)]
pub struct Var {
    /// Value reference (unique across all types within one model).
    pub vr: u32,
    /// Name.
    pub name: String,
    /// Base type (an Enumeration is accessed as Integer).
    pub ty: Type,
    /// The Enumeration type, for Integer variables declared as one.
    pub declared: Option<&'static EnumType>,
    /// Causality.
    pub causality: Causality,
    /// Variability.
    pub variability: Variability,
    /// Unit (declared in `UnitDefinitions`).
    pub unit: Option<&'static str>,
    /// Start value (parameters and inputs).
    pub start: Option<Value>,
    /// Description.
    pub description: String,
    /// What it is bound to.
    pub key: Key,
}

impl Var {
    /// Whether the master may set it (parameters and inputs).
    pub fn settable(&self) -> bool {
        self.causality != Causality::Output
    }

    /// Element name of its type in the XML (`Enumeration` for a declared Enumeration).
    pub fn xml_type(&self) -> &'static str {
        if self.declared.is_some() {
            "Enumeration"
        } else {
            self.ty.xml()
        }
    }
}
