//! `decode -j N --summary`: each chunk's events go into a partial summary of its own (on a worker), merged
//! here into the run's in input order. What depends on the frames before the chunk is kept raw in the
//! partial (first stamps and count bytes per row, the first status, the odometers' first readings, positions
//! counted from the chunk's start) and resolved at the merge, so the report is the single pass's.

use super::{absorb_extreme, larger_abs, RowKey, Summary, MAX_OTHER_IDS};

impl Summary {
    /// An empty summary of one chunk, to be merged with [`Self::absorb`].
    pub(in crate::commands::decode) fn partial() -> Self {
        Self { partial: true, health: crate::health::Analyzer::partial(), ..Self::default() }
    }

    /// Whether [`Self::absorb`] merges `later` exactly: not when its identifiers or interface names
    /// overflowed into counted-only sets (a name or row already known here could not be told apart), nor
    /// when its new identifiers would overflow this summary's rows, nor when its health analysis kept too
    /// much before its first rest (`health::Analyzer::can_absorb`).
    pub(in crate::commands::decode) fn can_absorb(&self, later: &Summary) -> bool {
        if !later.interfaces.extra.is_empty() || later.interfaces.extra_overflow {
            return false;
        }
        if !self.health.can_absorb(&later.health) {
            return false;
        }
        let mut new_other = 0;
        for row in &later.ids {
            if row.key == RowKey::Other {
                return false;
            }
            if row.key.standard_index().is_none() && !self.other_index.contains(row.key) {
                new_other += 1;
            }
        }
        // Once the rows overflowed, a partial of known identifiers still merges.
        new_other == 0 || self.other_index.len() + new_other <= MAX_OTHER_IDS
    }

    /// The partial summary of the next chunk (see [`Self::can_absorb`]), merged as if its events had come
    /// here one by one.
    pub(in crate::commands::decode) fn absorb(&mut self, later: &Summary) {
        let before = self.frames;
        self.frames += later.frames;
        self.first = self.first.or(later.first);
        if later.last.is_some() {
            self.last = later.last;
        }
        for row in &later.ids {
            let index = self.row_of(row.key);
            self.ids[index].absorb(row);
        }
        for name in &later.interfaces.names {
            self.interfaces.see(name);
        }
        if !later.last_iface.is_empty() {
            self.last_iface.clone_from(&later.last_iface);
        }
        // The chunk's first status compared with the one before it, then the changes within the chunk.
        if let Some((state, wire, at)) = later.first_status {
            let at = at.after(before);
            self.note_mode_change(state.control_mode, wire, at);
            self.note_vehicle_change(&state, at);
            self.status.clone_from(&later.status);
        }
        for (at, text) in &later.events {
            self.note(at.after(before), text.clone());
        }
        self.events_not_listed += later.events_not_listed;
        let faults = self.system_faults.iter_mut().flatten().zip(later.system_faults.iter().flatten());
        let drivers = self.driver_faults.iter_mut().flatten().zip(later.driver_faults.iter().flatten());
        for (seen, more) in faults.chain(drivers) {
            seen.absorb(more, before);
        }
        absorb_extreme(&mut self.battery_min, later.battery_min, before, |value, best| value < best);
        absorb_extreme(&mut self.battery_max, later.battery_max, before, |value, best| value > best);
        absorb_extreme(&mut self.battery_last, later.battery_last, before, |_, _| true);
        for (wheel, more) in self.wheels.iter_mut().zip(&later.wheels) {
            wheel.absorb(more);
        }
        let speeds = [
            (&mut self.measured_linear, later.measured_linear),
            (&mut self.measured_angular, later.measured_angular),
            (&mut self.commanded_linear, later.commanded_linear),
            (&mut self.commanded_angular, later.commanded_angular),
        ];
        let motors = self.rpm.iter_mut().zip(later.rpm).chain(self.current.iter_mut().zip(later.current));
        for (slot, more) in speeds.into_iter().chain(motors) {
            absorb_extreme(slot, more, before, larger_abs);
        }
        for (count, more) in self.error_classes.iter_mut().zip(later.error_classes) {
            *count += more;
        }
        self.raw_frames += later.raw_frames;
        self.health.absorb(&later.health);
    }

    /// The row of `key`, a new one (last) if it has none.
    fn row_of(&mut self, key: RowKey) -> usize {
        if let Some(standard) = key.standard_index() {
            if let Some(index) = self.standard_index[standard].checked_sub(1) {
                return index as usize;
            }
        }
        self.new_or_other_row(key)
    }
}

#[cfg(test)]
mod tests {
    use super::super::{At, Summary};
    use crate::candump::Timestamp;
    use crate::commands::decode::InputStats;
    use crate::output::{Event, FrameRef};
    use crate::protocol::detect::ProtocolDetector;
    use crate::protocol::message::{Message, MotionState, MotorDriverState, Odometry, SystemState, Wire};
    use crate::protocol::{CanFrame, Decoded};

    /// A frame of row `id` at `millis` after a fixed second, decoded as `message` (V1 wire: count bytes on).
    struct Input {
        frame: CanFrame,
        millis: u64,
        message: Option<Message>,
    }

    fn input(id: u32, millis: u64, message: Option<Message>) -> Input {
        Input { frame: CanFrame::new(id, &[0; 8]).unwrap(), millis, message }
    }

    fn feed(summary: &mut Summary, inputs: &[Input]) {
        for input in inputs {
            let decoded = input.message.map(|message| Decoded { wire: Wire::CanV1, message });
            let ts = Timestamp::from_numeric(
                1_700_000_000 + input.millis / 1000,
                (input.millis % 1000) as u32 * 1_000_000,
            );
            let event = Event {
                ts: Some(ts),
                iface: "can0",
                dir: None,
                frame: FrameRef::Can(&input.frame),
                decoded: Ok(decoded),
            };
            summary.event(&event);
        }
    }

    fn whole(inputs: &[Input]) -> Summary {
        let mut summary = Summary::default();
        feed(&mut summary, inputs);
        summary
    }

    /// The inputs cut at `cuts`, each piece summarized on its own and merged in order.
    fn merged(inputs: &[Input], cuts: &[usize]) -> Summary {
        let mut summary = Summary::default();
        let mut from = 0;
        for &to in cuts.iter().chain([inputs.len()].iter()) {
            let mut partial = Summary::partial();
            feed(&mut partial, &inputs[from..to]);
            assert!(summary.can_absorb(&partial));
            summary.absorb(&partial);
            from = to;
        }
        summary
    }

    fn reports(summary: &Summary) -> (String, String) {
        let (stats, detector) = (InputStats::default(), ProtocolDetector::default());
        (summary.report(&stats, &detector), summary.to_json(&stats, &detector).to_string())
    }

    /// Every single cut and every pair of cuts give the single pass's report, text and JSON.
    fn assert_every_cut_is_exact(inputs: &[Input]) {
        let expected = reports(&whole(inputs));
        for first in 0..=inputs.len() {
            assert_eq!(reports(&merged(inputs, &[first])), expected, "cut at {first}");
            for second in first..=inputs.len() {
                assert_eq!(reports(&merged(inputs, &[first, second])), expected, "cuts at {first}, {second}");
            }
        }
    }

    fn driver(count: u8, rpm: i16) -> Option<Message> {
        Some(Message::MotorDriverState(MotorDriverState {
            motor: 1,
            rpm,
            count,
            ..MotorDriverState::default()
        }))
    }

    fn system(
        control_mode: u8,
        vehicle_state: u8,
        fault_code: u16,
        battery_decivolts: u16,
    ) -> Option<Message> {
        let state = SystemState {
            control_mode,
            vehicle_state,
            fault_code,
            battery_decivolts,
            ..SystemState::default()
        };
        Some(Message::SystemState(state))
    }

    #[test]
    fn the_worst_gap_may_span_the_boundary() {
        let inputs = [
            input(0x100, 1000, None),
            input(0x100, 1100, None),
            input(0x100, 4100, None),
            input(0x100, 4200, None),
        ];
        let summary = merged(&inputs, &[2]);
        let row = &summary.ids[0];
        assert_eq!((row.count, row.worst_gap_ns), (4, 3_000_000_000));
        assert_eq!(row.worst_gap_at, Some(Timestamp::from_numeric(1_700_000_004, 100_000_000)));
        assert_eq!(row.first, Some(Timestamp::from_numeric(1_700_000_001, 0)));
        assert_eq!(row.last, Some(Timestamp::from_numeric(1_700_000_004, 200_000_000)));
        assert_every_cut_is_exact(&inputs);
    }

    #[test]
    fn count_bytes_are_continued_across_the_boundary() {
        // 0xFF | 0x00 is the normal wrap; 0x00 | 0x00 a repeat; 0x00 | 0x03 loses two frames.
        let counts = [0xFE, 0xFF, 0x00, 0x00, 0x03];
        let inputs: Vec<Input> = counts
            .iter()
            .enumerate()
            .map(|(n, &count)| input(0x100, n as u64 * 10, driver(count, 0)))
            .collect();
        let at_wrap = &merged(&inputs, &[2]).ids[0];
        assert_eq!((at_wrap.counter_skips, at_wrap.counter_repeats, at_wrap.frames_lost), (1, 1, 2));
        let at_repeat = &merged(&inputs, &[3]).ids[0];
        assert_eq!((at_repeat.counter_skips, at_repeat.counter_repeats, at_repeat.frames_lost), (1, 1, 2));
        let at_skip = &merged(&inputs, &[4]).ids[0];
        assert_eq!((at_skip.counter_skips, at_skip.counter_repeats, at_skip.frames_lost), (1, 1, 2));
        assert_eq!(at_skip.last_counter, Some(0x03));
        assert_every_cut_is_exact(&inputs);
    }

    #[test]
    fn a_fault_set_in_one_chunk_and_cleared_in_the_next_keeps_its_timeline() {
        let inputs = [
            input(0x100, 0, system(1, 0, 0, 240)),
            input(0x100, 10, system(1, 0, 0x0001, 240)),
            input(0x100, 20, system(1, 0, 0x0001, 240)),
            input(0x100, 30, system(1, 0, 0, 240)),
            input(0x100, 40, system(1, 0, 0x0001, 240)),
        ];
        let summary = merged(&inputs, &[3]);
        let seen = summary.system_faults[1][0];
        let at = |frame, millis: u64| At {
            ts: Some(Timestamp::from_numeric(1_700_000_000, millis as u32 * 1_000_000)),
            frame,
        };
        assert_eq!((seen.frames, seen.first, seen.last), (3, Some(at(2, 10)), Some(at(5, 40))));
        assert_every_cut_is_exact(&inputs);
    }

    #[test]
    fn a_mode_change_at_the_boundary_is_listed_once_with_its_position() {
        let inputs = [
            input(0x100, 0, system(0, 0, 0, 240)),
            input(0x100, 10, system(0, 0, 0, 240)),
            input(0x100, 20, system(1, 0, 0, 240)),
            input(0x100, 30, system(1, 1, 0, 240)),
        ];
        let summary = merged(&inputs, &[2]);
        let listed: Vec<(u64, &str)> =
            summary.events.iter().map(|(at, text)| (at.frame, text.as_str())).collect();
        assert_eq!(
            listed,
            [
                (1, "control mode rc (first status)"),
                (1, "vehicle state normal (first status)"),
                (3, "control mode rc -> can"),
                (4, "vehicle state normal -> estop (E-stop pressed)"),
            ]
        );
        assert_every_cut_is_exact(&inputs);
    }

    /// The cap on listed events counts across chunks as in one pass.
    #[test]
    fn the_listed_events_are_capped_across_chunks() {
        let inputs: Vec<Input> =
            (0..300).map(|n| input(0x100, n, system((n % 2) as u8, 0, 0, 240))).collect();
        for cuts in [[100, 250], [5, 290], [200, 201]] {
            let summary = merged(&inputs, &cuts);
            assert_eq!((summary.events.len(), summary.events_not_listed), (200, 101));
            assert_eq!(reports(&summary), reports(&whole(&inputs)));
        }
    }

    #[test]
    fn extremes_tied_across_the_boundary_keep_the_earlier() {
        let speed =
            |linear_mm_s| Some(Message::MotionState(MotionState { linear_mm_s, ..MotionState::default() }));
        let inputs = [
            input(0x100, 0, speed(-500)),
            input(0x101, 5, system(1, 0, 0, 250)),
            input(0x100, 10, speed(500)),
            input(0x101, 15, system(1, 0, 0, 250)),
            input(0x102, 20, driver(0, -3000)),
            input(0x102, 30, driver(1, 3000)),
        ];
        let summary = merged(&inputs, &[2]);
        let linear = summary.measured_linear.unwrap();
        assert_eq!((linear.value, linear.at.frame), (-500, 1));
        let battery =
            (summary.battery_max.unwrap(), summary.battery_min.unwrap(), summary.battery_last.unwrap());
        assert_eq!((battery.0.at.frame, battery.1.at.frame, battery.2.at.frame), (2, 2, 4));
        let rpm = merged(&inputs, &[5]).rpm[0].unwrap();
        assert_eq!((rpm.value, rpm.at.frame), (-3000, 5));
        assert_every_cut_is_exact(&inputs);
    }

    #[test]
    fn wheels_travel_and_reset_across_the_boundary() {
        let odometer = |left_mm, right_mm| Some(Message::Odometry(Odometry { left_mm, right_mm }));
        let inputs = [
            input(0x100, 0, odometer(1000, 0)),
            input(0x100, 10, odometer(1200, 100)),
            input(0x100, 20, odometer(1700, 9000)),
            input(0x100, 30, odometer(1600, 9100)),
        ];
        let summary = merged(&inputs, &[2]);
        let [left, right] = &summary.wheels;
        assert_eq!((left.travelled_mm, left.resets, left.first, left.last), (800, 0, Some(1000), Some(1600)));
        assert_eq!(
            (right.travelled_mm, right.resets, right.first, right.last),
            (200, 1, Some(0), Some(9100))
        );
        assert_every_cut_is_exact(&inputs);
    }

    /// Rows keep the order of first appearance, whichever chunk brought them.
    #[test]
    fn rows_and_interfaces_keep_the_order_of_first_appearance() {
        let inputs = [
            input(0x300, 0, None),
            input(0x100, 10, None),
            input(0x200, 20, None),
            input(0x100, 30, None),
            input(0x300, 40, None),
        ];
        let summary = merged(&inputs, &[1]);
        let rows: Vec<(String, u64)> =
            summary.ids.iter().map(|row| (row.key.to_string(), row.count)).collect();
        assert_eq!(rows, [("0x300".into(), 2), ("0x100".into(), 2), ("0x200".into(), 1)]);
        assert_every_cut_is_exact(&inputs);
    }

    /// What cannot be merged exactly is refused (the chunk is replayed instead): names or identifiers past
    /// the listed ones in the partial, or new identifiers that would overflow the run's rows.
    #[test]
    fn partials_past_the_listed_names_and_rows_are_refused() {
        let frame = CanFrame::new(0x100, &[]).unwrap();
        let mut names = Summary::partial();
        for n in 0..65 {
            let iface = format!("can{n}");
            names.event(&Event {
                ts: None,
                iface: &iface,
                dir: None,
                frame: FrameRef::Can(&frame),
                decoded: Ok(None),
            });
        }
        assert_eq!((names.interfaces.names.len(), names.interfaces.extra.len()), (64, 1));
        assert!(!Summary::default().can_absorb(&names));
        let extended: Vec<CanFrame> =
            (0..4097).map(|n| CanFrame::new_extended(0x10_0000 + n, &[]).unwrap()).collect();
        let event = |frame| Event {
            ts: None,
            iface: "can0",
            dir: None,
            frame: FrameRef::Can(frame),
            decoded: Ok(None),
        };
        let mut overflowed = Summary::partial();
        for frame in &extended {
            overflowed.event(&event(frame));
        }
        assert!(!Summary::default().can_absorb(&overflowed));
        // 4000 rows here and 96 new ones fill the rows exactly; one more would go to the overflow row.
        let (mut run, mut fits, mut one_more) = (Summary::default(), Summary::partial(), Summary::partial());
        for frame in &extended[..4000] {
            run.event(&event(frame));
        }
        for frame in &extended[3990..4096] {
            fits.event(&event(frame));
        }
        for frame in &extended[3990..4097] {
            one_more.event(&event(frame));
        }
        assert!(run.can_absorb(&fits));
        assert!(!run.can_absorb(&one_more));
        run.absorb(&fits);
        assert_eq!((run.ids.len(), run.ids[3995].count), (4096, 2));
        // Past the rows, known identifiers still merge; a new one (the overflow row's) does not.
        run.event(&event(&extended[4096]));
        let (mut known, mut new) = (Summary::partial(), Summary::partial());
        known.event(&event(&extended[7]));
        new.event(&event(&extended[4096]));
        assert!(run.can_absorb(&known));
        assert!(!run.can_absorb(&new));
    }
}
