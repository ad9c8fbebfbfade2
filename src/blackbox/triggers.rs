//! PLACEHOLDER until the trigger watcher lands (helper branch `triggers`): the API the recorder calls.

use crate::candump::Timestamp;
use crate::protocol::LinkFrame;

pub struct Trigger {
    pub at: Timestamp,
    pub cause: Cause,
}

#[derive(Clone, Debug, PartialEq)]
pub enum Cause {
    Mark { note: String },
}

impl Cause {
    pub fn slug(&self) -> &'static str {
        "mark"
    }
    pub fn describe(&self) -> String {
        match self {
            Cause::Mark { note } => format!("marked: {note}"),
        }
    }
}

#[derive(Clone, Debug)]
pub struct Expression(String);

impl std::str::FromStr for Expression {
    type Err = String;
    fn from_str(text: &str) -> Result<Self, String> {
        Ok(Self(text.to_string()))
    }
}

impl Expression {
    pub fn text(&self) -> &str {
        &self.0
    }
}

#[derive(Clone, Debug)]
pub struct TriggerSettings {
    pub defaults: bool,
    pub expressions: Vec<Expression>,
    pub battery_warning_volts: f64,
    pub rearm: std::time::Duration,
}

impl Default for TriggerSettings {
    fn default() -> Self {
        Self {
            defaults: true,
            expressions: Vec::new(),
            battery_warning_volts: 22.5,
            rearm: std::time::Duration::from_secs(1),
        }
    }
}

pub struct Watcher;

impl Watcher {
    pub fn new(_settings: TriggerSettings) -> Self {
        Self
    }
    pub fn frame(&mut self, _at: Timestamp, _frame: &LinkFrame, _out: &mut Vec<Trigger>) {}
    pub fn tick(&mut self, _now: Timestamp, _out: &mut Vec<Trigger>) {}
    pub fn state(&self) -> serde_json::Value {
        serde_json::Value::Null
    }
}
