//! The vocabulary of the fuzzer: one [`Op`] per way of calling one of the 34 functions, with
//! the hostile arguments a master could pass, and the proptest strategies that draw them.
//!
//! What is never generated, because no C API can defend against it: a component pointer that
//! is dangling (freed) or points to less memory than an instance header, and a count `n`
//! with a non-NULL array shorter than `n` (the callee may read `n` elements). Everything the
//! standard lets a caller get wrong is: NULL where a pointer is required, any count with NULL
//! arrays, unknown value references, values of any bit pattern, foreign or freed FMU-state
//! pointers, corrupted and crafted serialized states, and calls in every order.
use proptest::prelude::*;
use proptest::sample::Index;

/// Instances a sequence can hold at once.
pub const SLOTS: u8 = 3;

/// The component pointer a call receives.
#[derive(Debug, Clone, Copy)]
pub enum Target {
    /// The instance in this slot, when there is one (else the op is skipped).
    Slot(u8),
    Null,
    /// A pointer to zeroed memory that is not an instance (another library's component).
    Foreign,
}

/// A value reference: declared for the accessed type, declared for any type, or arbitrary.
#[derive(Debug, Clone, Copy)]
pub enum VrPick {
    OfKind(Index),
    Declared(Index),
    Raw(u32),
}

/// Which of the two arrays of a get/set is NULL. `huge_count` (only with both NULL, so that
/// nothing can be read) passes an `nvr` no memory could hold.
#[derive(Debug, Clone, Copy)]
pub struct Nulls {
    pub vr: bool,
    pub value: bool,
    pub huge_count: bool,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Kind {
    Real,
    Integer,
    Boolean,
    String,
}

#[derive(Debug, Clone)]
pub enum Text {
    Valid(String),
    Null,
    /// Bytes that are not UTF-8.
    Invalid(Vec<u8>),
}

#[derive(Debug, Clone)]
pub enum Category {
    Known(Index),
    Unknown(String),
    Null,
}

#[derive(Debug, Clone, Copy)]
pub enum NameArg {
    Valid,
    Empty,
    Null,
}

#[derive(Debug, Clone, Copy)]
pub enum GuidArg {
    Valid,
    Null,
    /// The right GUID with one character changed.
    Altered(Index),
    Garbage,
}

#[derive(Debug, Clone, Copy)]
pub enum CallbacksArg {
    Valid,
    NullStruct,
    NullLogger,
}

/// Where `fmi2GetFMUstate`/`fmi2FreeFMUstate`/`fmi2DeSerializeFMUstate` write the state.
#[derive(Debug, Clone, Copy)]
pub enum StateSlot {
    /// The `fmi2FMUstate*` itself is NULL.
    NullPointer,
    /// Points to a NULL state: a new state is made.
    Fresh,
    /// Points to a state seen before (live or freed, this instance's or another's).
    Existing(Index),
}

/// An `fmi2FMUstate` argument.
#[derive(Debug, Clone, Copy)]
pub enum StateArg {
    Null,
    Seen(Index),
    Foreign,
}

/// The bytes given to `fmi2DeSerializeFMUstate`.
#[derive(Debug, Clone)]
pub enum Buffer {
    Serialized(Index),
    /// One byte xor-ed with a non-zero mask.
    Flipped(Index, Index, u8),
    Truncated(Index, Index),
    Extended(Index, Vec<u8>),
    /// A payload byte changed and the checksum recomputed: passes every integrity check,
    /// so the decoder alone must cope (see `Session::tainted`).
    Crafted(Index, Index, u8),
    Garbage(Vec<u8>),
    /// NULL with a non-zero size.
    Null(usize),
}

#[derive(Debug, Clone, Copy)]
pub enum TimeArg {
    Current,
    /// The current time plus `factor` times max(1, |t|): inside or outside the tolerance.
    Offset(f64),
    Raw(f64),
}

#[derive(Debug, Clone)]
pub enum Op {
    TypesPlatform,
    Version,
    Instantiate {
        slot: u8,
        name: NameArg,
        fmu_type: i32,
        guid: GuidArg,
        callbacks: CallbacksArg,
        visible: i32,
        logging_on: i32,
    },
    FreeInstance(Target),
    SetDebugLogging {
        target: Target,
        on: i32,
        /// `None`: a NULL array with this count.
        categories: Result<Vec<Category>, usize>,
    },
    SetupExperiment {
        target: Target,
        tolerance_defined: i32,
        tolerance: f64,
        start: f64,
        stop_defined: i32,
        stop: f64,
    },
    EnterInitializationMode(Target),
    ExitInitializationMode(Target),
    Terminate(Target),
    Reset(Target),
    Get {
        target: Target,
        kind: Kind,
        vrs: Vec<VrPick>,
        nulls: Nulls,
    },
    SetReal {
        target: Target,
        vrs: Vec<VrPick>,
        values: Vec<f64>,
        nulls: Nulls,
    },
    SetInteger {
        target: Target,
        vrs: Vec<VrPick>,
        values: Vec<i32>,
        nulls: Nulls,
    },
    SetBoolean {
        target: Target,
        vrs: Vec<VrPick>,
        values: Vec<i32>,
        nulls: Nulls,
    },
    SetString {
        target: Target,
        vrs: Vec<VrPick>,
        values: Vec<Text>,
        nulls: Nulls,
    },
    GetFmuState {
        target: Target,
        slot: StateSlot,
    },
    SetFmuState {
        target: Target,
        state: StateArg,
    },
    FreeFmuState {
        target: Target,
        slot: StateSlot,
    },
    SerializedSize {
        target: Target,
        state: StateArg,
        size_null: bool,
    },
    Serialize {
        target: Target,
        state: StateArg,
        /// Added to the right size (buffers are always allocated with the size passed).
        size_error: i8,
        buffer_null: bool,
    },
    Deserialize {
        target: Target,
        buffer: Buffer,
        slot: StateSlot,
    },
    DirectionalDerivative {
        target: Target,
        vrs: Vec<VrPick>,
    },
    SetRealInputDerivatives {
        target: Target,
        vrs: Vec<VrPick>,
        order: i32,
        value: f64,
    },
    GetRealOutputDerivatives {
        target: Target,
        vrs: Vec<VrPick>,
        order: i32,
    },
    DoStep {
        target: Target,
        t: TimeArg,
        h: f64,
        no_set_prior: i32,
    },
    CancelStep(Target),
    /// `which`: 0 fmi2GetStatus, 1 Real, 2 Integer, 3 Boolean, 4 String.
    Status {
        target: Target,
        which: u8,
        kind: i32,
        value_null: bool,
    },
    /// A legal setup + enter + exit with legal arguments (3 calls): reaches the deep states.
    LegalInit(u8),
    /// `n` legal steps (set inputs, get outputs, do step) from the tracked time.
    LegalSteps(u8, u8),
}

/// A Real argument: mostly ordinary, often special.
pub fn real() -> impl Strategy<Value = f64> {
    prop_oneof![
        6 => -1.0e3..1.0e3f64,
        1 => -1.0e12..1.0e12f64,
        1 => prop::sample::select(vec![
            0.0, -0.0, f64::NAN, -f64::NAN, f64::INFINITY, f64::NEG_INFINITY, f64::MAX, f64::MIN,
            f64::MIN_POSITIVE, 5e-324, -5e-324, 1e300, -1e300, 1e-300, f64::EPSILON,
        ]),
        1 => any::<f64>(),
    ]
}

/// A communication step size: usually sensible, sometimes zero, negative, tiny, huge or not
/// a number.
pub fn step_size() -> impl Strategy<Value = f64> {
    prop_oneof![
        8 => prop::sample::select(vec![0.01, 0.1, 0.001, 0.05, 1.0]),
        2 => 1e-6..2.0f64,
        2 => real(),
        1 => prop::sample::select(vec![1e6, 1e9, 1e300, f64::MAX, f64::MIN_POSITIVE, 5e-324]),
    ]
}

fn integer() -> impl Strategy<Value = i32> {
    prop_oneof![
        4 => -3..6i32,
        1 => prop::sample::select(vec![i32::MIN, i32::MAX, -1, 1000]),
        1 => any::<i32>(),
    ]
}

fn target() -> impl Strategy<Value = Target> {
    prop_oneof![
        30 => (0..SLOTS).prop_map(Target::Slot),
        1 => Just(Target::Null),
        1 => Just(Target::Foreign),
    ]
}

fn vr_pick() -> impl Strategy<Value = VrPick> {
    prop_oneof![
        8 => any::<Index>().prop_map(VrPick::OfKind),
        1 => any::<Index>().prop_map(VrPick::Declared),
        1 => prop_oneof![any::<u32>(), Just(u32::MAX), 0..300u32].prop_map(VrPick::Raw),
    ]
}

fn vrs() -> impl Strategy<Value = Vec<VrPick>> {
    prop::collection::vec(vr_pick(), 0..6)
}

fn nulls() -> impl Strategy<Value = Nulls> {
    prop_oneof![
        20 => Just(Nulls { vr: false, value: false, huge_count: false }),
        1 => Just(Nulls { vr: true, value: false, huge_count: false }),
        1 => Just(Nulls { vr: false, value: true, huge_count: false }),
        1 => any::<bool>().prop_map(|huge_count| Nulls { vr: true, value: true, huge_count }),
    ]
}

fn text() -> impl Strategy<Value = Text> {
    prop_oneof![
        4 => "[a-z%0-9 ]{0,12}".prop_map(Text::Valid),
        1 => Just(Text::Null),
        1 => prop::collection::vec(0x80..=0xffu8, 1..4).prop_map(Text::Invalid),
    ]
}

fn state_slot() -> impl Strategy<Value = StateSlot> {
    prop_oneof![
        1 => Just(StateSlot::NullPointer),
        6 => Just(StateSlot::Fresh),
        3 => any::<Index>().prop_map(StateSlot::Existing),
    ]
}

fn state_arg() -> impl Strategy<Value = StateArg> {
    prop_oneof![
        1 => Just(StateArg::Null),
        8 => any::<Index>().prop_map(StateArg::Seen),
        1 => Just(StateArg::Foreign),
    ]
}

fn buffer() -> impl Strategy<Value = Buffer> {
    prop_oneof![
        4 => any::<Index>().prop_map(Buffer::Serialized),
        3 => (any::<Index>(), any::<Index>(), 1..=255u8).prop_map(|(b, at, mask)| Buffer::Flipped(b, at, mask)),
        2 => (any::<Index>(), any::<Index>()).prop_map(|(b, len)| Buffer::Truncated(b, len)),
        1 => (any::<Index>(), prop::collection::vec(any::<u8>(), 1..9)).prop_map(|(b, tail)| Buffer::Extended(b, tail)),
        3 => (any::<Index>(), any::<Index>(), 1..=255u8).prop_map(|(b, at, mask)| Buffer::Crafted(b, at, mask)),
        1 => prop::collection::vec(any::<u8>(), 0..128).prop_map(Buffer::Garbage),
        1 => prop_oneof![1..64usize, Just(usize::MAX)].prop_map(Buffer::Null),
    ]
}

fn time_arg() -> impl Strategy<Value = TimeArg> {
    prop_oneof![
        12 => Just(TimeArg::Current),
        2 => prop::sample::select(vec![1e-13, -1e-13, 5e-10, -5e-10, 1e-6, -1e-6, 1.0])
            .prop_map(TimeArg::Offset),
        1 => real().prop_map(TimeArg::Raw),
    ]
}

fn instantiate() -> impl Strategy<Value = Op> {
    (
        0..SLOTS,
        prop_oneof![8 => Just(NameArg::Valid), 1 => Just(NameArg::Empty), 1 => Just(NameArg::Null)],
        prop_oneof![8 => Just(1), 1 => Just(0), 1 => any::<i32>()],
        prop_oneof![
            8 => Just(GuidArg::Valid),
            1 => Just(GuidArg::Null),
            1 => any::<Index>().prop_map(GuidArg::Altered),
            1 => Just(GuidArg::Garbage),
        ],
        prop_oneof![
            10 => Just(CallbacksArg::Valid),
            1 => Just(CallbacksArg::NullStruct),
            1 => Just(CallbacksArg::NullLogger),
        ],
        prop_oneof![Just(0), Just(1), any::<i32>()],
        prop_oneof![3 => Just(0), 1 => Just(1), 1 => any::<i32>()],
    )
        .prop_map(
            |(slot, name, fmu_type, guid, callbacks, visible, logging_on)| Op::Instantiate {
                slot,
                name,
                fmu_type,
                guid,
                callbacks,
                visible,
                logging_on,
            },
        )
}

fn get_set() -> impl Strategy<Value = Op> {
    let kind = prop_oneof![
        6 => Just(Kind::Real),
        2 => Just(Kind::Integer),
        1 => Just(Kind::Boolean),
        1 => Just(Kind::String),
    ];
    // Values are drawn as long as the references; a set passes min(len) pairs.
    prop_oneof![
        3 => (target(), kind, vrs(), nulls()).prop_map(|(target, kind, vrs, nulls)| Op::Get { target, kind, vrs, nulls }),
        4 => (target(), vrs(), prop::collection::vec(real(), 6), nulls()).prop_map(|(target, vrs, values, nulls)| Op::SetReal { target, vrs, values, nulls }),
        1 => (target(), vrs(), prop::collection::vec(integer(), 6), nulls()).prop_map(|(target, vrs, values, nulls)| Op::SetInteger { target, vrs, values, nulls }),
        1 => (target(), vrs(), prop::collection::vec(prop_oneof![Just(0), Just(1), any::<i32>()], 6), nulls()).prop_map(|(target, vrs, values, nulls)| Op::SetBoolean { target, vrs, values, nulls }),
        1 => (target(), vrs(), prop::collection::vec(text(), 6), nulls()).prop_map(|(target, vrs, values, nulls)| Op::SetString { target, vrs, values, nulls }),
    ]
}

fn fmu_state() -> impl Strategy<Value = Op> {
    prop_oneof![
        3 => (target(), state_slot()).prop_map(|(target, slot)| Op::GetFmuState { target, slot }),
        3 => (target(), state_arg()).prop_map(|(target, state)| Op::SetFmuState { target, state }),
        2 => (target(), state_slot()).prop_map(|(target, slot)| Op::FreeFmuState { target, slot }),
        1 => (target(), state_arg(), prop::bool::weighted(0.1)).prop_map(|(target, state, size_null)| Op::SerializedSize { target, state, size_null }),
        3 => (target(), state_arg(), prop_oneof![6 => Just(0i8), 1 => any::<i8>()], prop::bool::weighted(0.1))
            .prop_map(|(target, state, size_error, buffer_null)| Op::Serialize { target, state, size_error, buffer_null }),
        4 => (target(), buffer(), state_slot()).prop_map(|(target, buffer, slot)| Op::Deserialize { target, buffer, slot }),
    ]
}

fn lifecycle() -> impl Strategy<Value = Op> {
    prop_oneof![
        2 => target().prop_map(Op::FreeInstance),
        2 => (target(), prop_oneof![Just(0), Just(1), any::<i32>()], prop_oneof![
                4 => prop::collection::vec(prop_oneof![
                    6 => any::<Index>().prop_map(Category::Known),
                    1 => "[a-zA-Z]{0,10}".prop_map(Category::Unknown),
                    1 => Just(Category::Null),
                ], 0..4).prop_map(Ok),
                1 => prop_oneof![Just(0usize), 1..8usize, Just(usize::MAX)].prop_map(Err),
            ])
            .prop_map(|(target, on, categories)| Op::SetDebugLogging { target, on, categories }),
        3 => (target(), any::<i32>(), real(), prop_oneof![4 => Just(0.0), 1 => real()], prop_oneof![Just(0), Just(1)], prop_oneof![Just(200.0), real()])
            .prop_map(|(target, tolerance_defined, tolerance, start, stop_defined, stop)| Op::SetupExperiment {
                target, tolerance_defined, tolerance, start, stop_defined, stop,
            }),
        3 => target().prop_map(Op::EnterInitializationMode),
        3 => target().prop_map(Op::ExitInitializationMode),
        1 => target().prop_map(Op::Terminate),
        2 => target().prop_map(Op::Reset),
        3 => (0..SLOTS).prop_map(Op::LegalInit),
        3 => (0..SLOTS, 1..40u8).prop_map(|(slot, n)| Op::LegalSteps(slot, n)),
    ]
}

fn stepping() -> impl Strategy<Value = Op> {
    prop_oneof![
        8 => (target(), time_arg(), step_size(), prop_oneof![Just(0), Just(1), any::<i32>()])
            .prop_map(|(target, t, h, no_set_prior)| Op::DoStep { target, t, h, no_set_prior }),
        1 => target().prop_map(Op::CancelStep),
        3 => (target(), 0..5u8, prop_oneof![4 => 0..4i32, 1 => any::<i32>()], prop::bool::weighted(0.1))
            .prop_map(|(target, which, kind, value_null)| Op::Status { target, which, kind, value_null }),
        1 => (target(), vrs()).prop_map(|(target, vrs)| Op::DirectionalDerivative { target, vrs }),
        1 => (target(), vrs(), integer(), real()).prop_map(|(target, vrs, order, value)| Op::SetRealInputDerivatives { target, vrs, order, value }),
        1 => (target(), vrs(), integer()).prop_map(|(target, vrs, order)| Op::GetRealOutputDerivatives { target, vrs, order }),
    ]
}

/// One call (or legal macro) of any kind.
pub fn op() -> impl Strategy<Value = Op> {
    prop_oneof![
        1 => prop_oneof![Just(Op::TypesPlatform), Just(Op::Version)],
        3 => instantiate(),
        8 => lifecycle(),
        10 => get_set(),
        8 => fmu_state(),
        8 => stepping(),
    ]
}

/// A call sequence. Slot 0 starts with a valid instance (see `Session::new`), so even short
/// sequences reach the functions that need one.
pub fn sequence(max_len: usize) -> impl Strategy<Value = Vec<Op>> {
    prop::collection::vec(op(), 1..=max_len)
}
