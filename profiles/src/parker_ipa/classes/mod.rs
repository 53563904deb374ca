//! The vendor classes and services: [`class64`], class 0x64 "ACR Parameter", services
//! 0x50-0x54; [`class65`], class 0x65 "ACR Group", 0x53 Read Group and 0x34 Write Binary,
//! whose ACR binary commands [`binary`] decodes and runs;
//! [`tags`], the tag services 0x4C/0x4D/0x48/0x4E on "P4012" symbolic paths.

pub mod binary;
pub mod class64;
pub mod class65;
pub mod tags;
