//! Reading and writing candump / cansend text.
