//! VBA's run-time errors: the one table of their numbers and messages, which `Err.Raise n`
//! without a description, `Err.Description`, the `Error` function and every error the macro
//! runtime raises read; and `Error(n)` / `Error$(n)` itself.
//!
//! The messages are those of the "Trappable errors" page of the Office VBA language reference
//! (learn.microsoft.com/office/vba/language/reference/user-interface-help/trappable-errors).
//! Where that table shortens a message, the error's own page gives the text VBA shows, and
//! that is the one kept (noted in the table). A number the table has not is "Application-defined
//! or object-defined error", which is what `Error` gives for such a number ("Error function").

use std::fmt::Display;

use crate::eval::coerce::to_number;
use crate::eval::functions::api::Ctx;
use crate::eval::value::{Value, XlResult};
use crate::formula::ast::Expr;

use super::{invalid_call, invalid_use_of_null, VBA_DATES};

/// What VBA says of an error number it does not define ("Error function"; also Excel's 1004
/// raised by `Err.Raise 1004`).
pub const APPLICATION_DEFINED: &str = "Application-defined or object-defined error";

/// The largest error number: "Visual Basic errors (both Visual Basic-defined and user-defined
/// errors) are in the range 0–65535" ("Raise method").
pub const MAX_ERROR_NUMBER: u32 = 65535;

/// The code of ncsheet's own refusal of something VBA or Excel would do (a member, an argument
/// or a form ncsheet has no code for): past any error number VBA has, so no `On Error` traps it
/// and no `Err.Number` shows it. Skipping the refused statement, as a trapped error would, lets
/// the macro go on without its effect: a silent wrong result (issue 31).
pub const NOT_SUPPORTED: u32 = u32::MAX - 2;

/// Microsoft's "Trappable errors" table, in order of number.
const TRAPPABLE: &[(u32, &str)] = &[
    (3, "Return without GoSub"),
    // The table says "Invalid procedure call"; the error's page, "Invalid procedure call or
    // argument (Error 5)", gives the whole message.
    (5, "Invalid procedure call or argument"),
    (6, "Overflow"),
    (7, "Out of memory"),
    (9, "Subscript out of range"),
    (10, "This array is fixed or temporarily locked"),
    (11, "Division by zero"),
    (13, "Type mismatch"),
    (14, "Out of string space"),
    (16, "Expression too complex"),
    (17, "Can't perform requested operation"),
    (18, "User interrupt occurred"),
    (20, "Resume without error"),
    (28, "Out of stack space"),
    (35, "Sub, Function, or Property not defined"),
    (47, "Too many code resource or DLL application clients"),
    (48, "Error in loading code resource or DLL"),
    (49, "Bad code resource or DLL calling convention"),
    (51, "Internal error"),
    (52, "Bad file name or number"),
    (53, "File not found"),
    (54, "Bad file mode"),
    (55, "File already open"),
    (57, "Device I/O error"),
    (58, "File already exists"),
    (59, "Bad record length"),
    (61, "Disk full"),
    (62, "Input past end of file"),
    (63, "Bad record number"),
    (67, "Too many files"),
    (68, "Device unavailable"),
    (70, "Permission denied"),
    (71, "Disk not ready"),
    (74, "Can't rename with different drive"),
    (75, "Path/File access error"),
    (76, "Path not found"),
    (91, "Object variable or With block variable not set"),
    (92, "For loop not initialized"),
    (93, "Invalid pattern string"),
    (94, "Invalid use of Null"),
    (97, "Can't call Friend procedure on an object that is not an instance of the defining class"),
    (98, "A property or method call cannot include a reference to a private object, either as an argument or as a return value"),
    (298, "System resource or DLL could not be loaded"),
    (320, "Can't use character device names in specified file names"),
    (321, "Invalid file format"),
    (322, "Can't create necessary temporary file"),
    (325, "Invalid format in resource file"),
    (327, "Data value named not found"),
    (328, "Illegal parameter; can't write arrays"),
    (335, "Could not access system registry"),
    (336, "Component not correctly registered"),
    (337, "Component not found"),
    (338, "Component did not run correctly"),
    (360, "Object already loaded"),
    (361, "Can't load or unload this object"),
    (363, "Control specified not found"),
    (364, "Object was unloaded"),
    (365, "Unable to unload within this context"),
    (368, "The specified file is out of date. This program requires a later version"),
    (371, "The specified object can't be used as an owner form for Show"),
    (380, "Invalid property value"),
    (381, "Invalid property-array index"),
    (382, "Property Set can't be executed at run time"),
    (383, "Property Set can't be used with a read-only property"),
    (385, "Need property-array index"),
    (387, "Property Set not permitted"),
    (393, "Property Get can't be executed at run time"),
    (394, "Property Get can't be executed on write-only property"),
    (400, "Form already displayed; can't show modally"),
    (402, "Code must close topmost modal form first"),
    (419, "Permission to use object denied"),
    (422, "Property not found"),
    (423, "Property or method not found"),
    (424, "Object required"),
    (425, "Invalid object use"),
    (429, "Component can't create object or return reference to this object"),
    (430, "Class doesn't support Automation"),
    (432, "File name or class name not found during Automation operation"),
    (438, "Object doesn't support this property or method"),
    (440, "Automation error"),
    (442, "Connection to type library or object library for remote process has been lost"),
    (443, "Automation object doesn't have a default value"),
    (445, "Object doesn't support this action"),
    (446, "Object doesn't support named arguments"),
    (447, "Object doesn't support current locale setting"),
    (448, "Named argument not found"),
    // The table adds "or invalid property assignment"; the error's page is "Argument not
    // optional (Error 449)".
    (449, "Argument not optional"),
    (450, "Wrong number of arguments or invalid property assignment"),
    // The table says "Object not a collection"; the error's page is "Property let procedure
    // not defined and property get procedure did not return an object (Error 451)".
    (451, "Property let procedure not defined and property get procedure did not return an object"),
    (452, "Invalid ordinal"),
    (453, "Specified code resource not found"),
    (454, "Code resource not found"),
    (455, "Code resource lock error"),
    (457, "This key is already associated with an element of this collection"),
    (458, "Variable uses a type not supported in Visual Basic"),
    (459, "This component doesn't support the set of events"),
    (460, "Invalid Clipboard format"),
    (461, "Method or data member not found"),
    (462, "The remote server machine does not exist or is unavailable"),
    (463, "Class not registered on local machine"),
    (480, "Can't create AutoRedraw image"),
    (481, "Invalid picture"),
    (482, "Printer error"),
    (483, "Printer driver does not support specified property"),
    (484, "Problem getting printer information from the system. Make sure the printer is set up correctly"),
    (485, "Invalid picture type"),
    (486, "Can't print form image to this type of printer"),
    (520, "Can't empty Clipboard"),
    (521, "Can't open Clipboard"),
    (735, "Can't save file to TEMP directory"),
    (744, "Search text not found"),
    (746, "Replacements too long"),
    (31001, "Out of memory"),
    (31004, "No object"),
    (31018, "Class is not set"),
    (31027, "Unable to activate object"),
    (31032, "Unable to create embedded object"),
    (31036, "Error saving to file"),
    (31037, "Error loading from file"),
];

/// VBA's message for error `number` ("Trappable errors"); [`APPLICATION_DEFINED`] for a number
/// VBA does not define.
/// (A `const fn`, so that a module's named errors can be constants of the table's texts.)
pub const fn description(number: u32) -> &'static str {
    let (mut low, mut high) = (0, TRAPPABLE.len());
    while low < high {
        let mid = (low + high) / 2;
        let (n, text) = TRAPPABLE[mid];
        if n == number {
            return text;
        }
        if n < number {
            low = mid + 1;
        } else {
            high = mid;
        }
    }
    APPLICATION_DEFINED
}

/// The message of VBA's run-time error `number` raised by the runtime: its description, the
/// number, and why here (`err_state` keeps what is before the number as `Err.Description`).
pub fn message(number: u32, why: impl Display) -> String {
    format!("{} (run-time error {number}): {why}", description(number))
}

/// `Error(n)` / `Error$(n)` ("Error function"): the message of error `n`; "" for 0; a number
/// VBA does not define is "Application-defined or object-defined error"; a number that is no
/// error number (below 0 or past 65535) is run-time error 5, Null error 94.
pub(super) fn error_fn(ctx: &mut Ctx, args: &[Expr]) -> XlResult<Value> {
    let v = ctx.eval(&args[0]);
    if matches!(v, Value::Null) {
        return Err(invalid_use_of_null(ctx, "Error"));
    }
    // Passed as a Long: a fraction rounds half to even ([MS-VBAL] 5.5.1.2.1).
    let n = to_number(&v, VBA_DATES)?.round_ties_even();
    if !(0.0..=f64::from(MAX_ERROR_NUMBER)).contains(&n) {
        return Err(invalid_call(ctx, "Error", "an error number is from 0 to 65535"));
    }
    Ok(Value::text(match n as u32 {
        0 => "",
        number => description(number),
    }))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_table_is_in_order_of_number_for_its_binary_search() {
        assert!(TRAPPABLE.windows(2).all(|w| w[0].0 < w[1].0));
        for &(n, text) in TRAPPABLE {
            assert_eq!(description(n), text);
        }
        assert_eq!(description(4), APPLICATION_DEFINED);
        assert_eq!(description(65535), APPLICATION_DEFINED);
    }
}
